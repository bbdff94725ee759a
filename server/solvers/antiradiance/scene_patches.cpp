#include "solvers/antiradiance/scene_patches.h"

#include <glm/gtc/matrix_inverse.hpp>

namespace gistream::antiradiance {

glm::vec3 MaterialAlbedo(const SceneState& state, int material) {
  // Textures are not sampled per patch: the factor is the patch's albedo
  // (the view's display pass multiplies the per-pixel albedo).
  if (material < 0 || size_t(material) >= state.materials().size()) return glm::vec3(1.0f);
  return glm::vec3(state.materials()[size_t(material)].base_color_factor);
}

std::vector<std::vector<SourceTriangle>> SceneTriangles(const SceneState& state) {
  std::vector<std::vector<SourceTriangle>> groups;
  for (size_t n = 0; n < state.nodes().size(); ++n) {
    const Node& node = state.nodes()[n];
    if (node.mesh < 0) continue;
    const glm::mat4& world = state.world()[n];
    const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(world));
    for (const Primitive& prim : state.NodeMesh(n).primitives) {  // posed when it deforms
      std::vector<SourceTriangle> group;
      group.reserve(prim.indices.size() / 3);
      const glm::vec3 albedo = MaterialAlbedo(state, prim.material);
      for (size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
        SourceTriangle tri;
        glm::vec3 shading(0.0f);
        for (int k = 0; k < 3; ++k) {
          const uint32_t v = prim.indices[t + size_t(k)];
          tri.p[size_t(k)] = glm::vec3(world * glm::vec4(prim.positions[v], 1.0f));
          if (v < prim.normals.size()) shading += normal_matrix * prim.normals[v];
        }
        const glm::vec3 c = glm::cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]);
        const float len = glm::length(c);
        if (!(len > 0.0f)) continue;  // degenerate: no area, no light
        tri.normal = c / len;
        if (glm::dot(tri.normal, shading) < 0.0f) tri.normal = -tri.normal;
        tri.albedo = albedo;
        tri.tag = prim.material;
        group.push_back(tri);
      }
      if (!group.empty()) groups.push_back(std::move(group));
    }
  }
  return groups;
}

}  // namespace gistream::antiradiance
