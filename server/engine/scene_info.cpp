#include "engine/scene_info.h"

#include <glm/gtx/matrix_decompose.hpp>

namespace gistream {

SceneInfo DescribeScene(const SceneId& id, const SceneState& state) {
  const Scene& scene = state.scene();
  SceneInfo info;
  info.id = id;
  info.version = state.version();
  info.bounds = scene.bounds;
  info.triangle_count = scene.triangle_count;
  info.vertex_count = scene.vertex_count;
  info.has_environment = scene.environment.has_value();
  info.ignored_extensions = scene.ignored_extensions;
  info.import_warnings = scene.import_warnings;
  for (size_t i = 0; i < scene.animations.size(); ++i) {
    const Animation& a = scene.animations[i];
    info.animations.push_back({uint32_t(i), a.name, a.start, a.end});
  }
  for (size_t i = 0; i < state.nodes().size(); ++i) {
    const Node& n = state.nodes()[i];
    info.nodes.push_back(
        {uint32_t(i), n.name, n.parent, n.mesh, n.translation, n.rotation, n.scale});
  }
  for (size_t i = 0; i < state.lights().size(); ++i) {
    const LightInstance& l = state.lights()[i];
    info.lights.push_back(
        {uint32_t(i), l.light.name.empty() ? state.nodes()[size_t(l.node)].name : l.light.name,
         l.light.type, uint32_t(l.node), l.light.color, l.light.intensity, l.position, l.direction,
         l.light.inner_cone_angle, l.light.outer_cone_angle});
  }
  const std::vector<int> cameras = CameraInstanceNodes(scene);
  for (size_t i = 0; i < cameras.size(); ++i) {
    const int node = cameras[i];
    glm::vec3 scale, translation, skew;
    glm::vec4 perspective;
    glm::quat rotation;
    glm::decompose(state.world()[size_t(node)], scale, rotation, translation, skew, perspective);
    const Camera& c = scene.cameras[size_t(scene.nodes[size_t(node)].camera)];
    info.cameras.push_back({uint32_t(i), c.name.empty() ? scene.nodes[size_t(node)].name : c.name,
                            uint32_t(node), c.yfov, translation, glm::normalize(rotation)});
  }
  for (size_t i = 0; i < state.materials().size(); ++i) {
    const Material& m = state.materials()[i];
    info.materials.push_back({uint32_t(i), m.name, m.base_color_factor, m.emission(),
                              m.emissive_factor, m.emissive_strength});
  }
  for (const Node& n : scene.nodes) {
    if (n.mesh < 0) continue;
    for (const Primitive& p : scene.meshes[size_t(n.mesh)].primitives) {
      if (p.material >= 0 && state.materials()[size_t(p.material)].emissive()) {
        info.emissive_triangle_count += uint32_t(p.indices.size() / 3);
      }
    }
  }
  return info;
}

}  // namespace gistream
