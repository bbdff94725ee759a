#include "scene/gpu/scene_memory.h"

#include "scene/state/deform.h"

namespace gistream {
namespace {

uint64_t ImageBytes(const Image& image) {
  return uint64_t(image.pixels8.size()) + uint64_t(image.pixelsf.size()) * sizeof(float);
}

// One mesh's CPU geometry: vertex attributes, indices, proxy levels and
// clusters, morph targets.
uint64_t MeshBytes(const Mesh& mesh) {
  uint64_t geometry = 0;
  for (const Primitive& p : mesh.primitives) {
    geometry += p.positions.size() * sizeof(glm::vec3) + p.normals.size() * sizeof(glm::vec3) +
                p.uvs.size() * sizeof(glm::vec2) + p.indices.size() * sizeof(uint32_t) +
                p.joints.size() * sizeof(glm::u16vec4) + p.weights.size() * sizeof(glm::vec4);
    for (const ProxyLevel& level : p.proxies) geometry += level.indices.size() * sizeof(uint32_t);
    for (const ProxyCluster& c : p.clusters) {
      geometry +=
          sizeof(ProxyCluster) + (c.indices.size() + c.level.indices.size()) * sizeof(uint32_t);
    }
    for (const Primitive::MorphTarget& t : p.targets) {
      geometry += (t.positions.size() + t.normals.size()) * sizeof(glm::vec3);
    }
  }
  return geometry;
}

}  // namespace

SceneBytes CountSceneBytes(const Scene& scene) {
  SceneBytes bytes;
  uint64_t geometry = 0;
  for (const Mesh& mesh : scene.meshes) geometry += MeshBytes(mesh);
  // SceneState's posed copy of each deforming node's mesh (a whole copy,
  // re-posed on every deformation; scene_state.h).
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    if (NodeMeshDeforms(scene, n)) geometry += MeshBytes(scene.meshes[size_t(scene.nodes[n].mesh)]);
  }
  for (const Skin& skin : scene.skins) {
    geometry += skin.joints.size() * (sizeof(int) + sizeof(glm::mat4));
  }
  for (const Animation& a : scene.animations) {
    for (const AnimationSampler& s : a.samplers) {
      geometry += (s.times.size() + s.values.size()) * sizeof(float);
    }
  }
  bytes.cpu = geometry + scene.nodes.size() * sizeof(Node);
  // The GPU copy: the same vertex and index data (position, normal, uv per
  // vertex even where the file has none; proxy levels add indices only),
  // textures with mips (x 4/3).
  uint64_t vertices = 0, indices = 0;
  for (const Mesh& mesh : scene.meshes) {
    for (const Primitive& p : mesh.primitives) {
      vertices += p.positions.size();
      indices += p.indices.size();
      for (const ProxyLevel& level : p.proxies) indices += level.indices.size();  // proxies
      for (const ProxyCluster& c : p.clusters) indices += c.indices.size() + c.level.indices.size();
    }
  }
  bytes.gpu = vertices * (12 + 12 + 8) + indices * 4;
  // The G-buffer's draw list (render/view_passes.h): a command and a
  // record per primitive drawn, on the CPU and in a GL buffer.
  uint64_t draw_items = 0;
  for (const Node& node : scene.nodes) {
    if (node.mesh >= 0) draw_items += scene.meshes[size_t(node.mesh)].primitives.size();
  }
  bytes.cpu += draw_items * kDrawListBytesPerDraw;
  bytes.gpu += draw_items * kDrawListBytesPerDraw;
  for (const Image& image : scene.images) {
    bytes.cpu += ImageBytes(image);
    bytes.gpu += uint64_t(image.width) * uint64_t(image.height) * (image.is_float ? 16 : 4) * 4 / 3;
  }
  if (scene.environment) {
    const Image& env = scene.environment->image;
    bytes.cpu += ImageBytes(env);
    bytes.gpu += uint64_t(env.width) * uint64_t(env.height) * 16 * 4 / 3;
  }
  return bytes;
}

}  // namespace gistream
