#include "solvers/antiradiance/shared_elements.h"

#include <algorithm>
#include <map>
#include <memory>
#include <utility>

#include "solvers/antiradiance/scene_patches.h"
#include "solvers/hierarchy/element_tree.h"
#include "solvers/hierarchy/subdivide.h"
#include "solvers/hierarchy/surfels.h"

namespace gistream::antiradiance {
namespace {

int Emit(const hierarchy::Elements& e, const std::vector<glm::vec3>& albedo,
         const std::vector<int>& tag, int node, Patches& out) {
  const int id = out.size();
  const size_t n = size_t(node);
  out.position.push_back(e.position[n]);
  out.normal.push_back(e.normal[n]);
  out.area.push_back(e.area[n]);
  out.radius.push_back(e.radius[n]);
  const bool leaf = e.is_leaf(node);
  out.albedo.push_back(leaf && n < albedo.size() ? albedo[n] : glm::vec3(0.0f));
  out.tag.push_back(leaf && n < tag.size() ? tag[n] : -1);
  out.children.push_back({-1, -1, -1, -1});
  if (!leaf) {
    int k = 0;
    for (int c : e.children[n]) {
      if (c < 0) continue;
      const int child = Emit(e, albedo, tag, c, out);
      out.children[size_t(id)][size_t(k++)] = child;
    }
  }
  return id;
}

}  // namespace

Patches PatchesFromElements(const hierarchy::Elements& elements,
                            const std::vector<glm::vec3>& leaf_albedo,
                            const std::vector<int>& leaf_tag) {
  Patches out;
  for (int root : elements.roots())
    out.roots.push_back(Emit(elements, leaf_albedo, leaf_tag, root, out));
  return out;
}

Patches SurfelPatches(const SceneState& state, const GpuScene& gpu, SurfelCache& meshes) {
  const Scene& scene = state.scene();
  std::vector<hierarchy::ElementInstance> instances;
  std::vector<glm::mat4> world;
  std::vector<int> materials;
  for (const DrawItem& d : gpu.draws()) {
    auto& mesh = meshes[{d.mesh, d.primitive}];
    if (!mesh) {
      mesh = std::make_shared<hierarchy::ElementMesh>();
      // Long edges subdivided to the scene-sized limit (hierarchy/subdivide.h).
      mesh->surfels = hierarchy::CreateSurfels(hierarchy::SubdivideLongEdges(
          scene.meshes[size_t(d.mesh)].primitives[size_t(d.primitive)],
          hierarchy::LocalMaxEdge(state, gpu, d.mesh, d.primitive)));
      mesh->tree = hierarchy::CreateHierarchy(mesh->surfels);
    }
    instances.push_back({mesh, 0, {}});
    world.push_back(state.world()[size_t(d.node)]);
    materials.push_back(d.material);
  }
  hierarchy::Elements elements(std::move(instances));
  elements.Update(world);
  std::vector<glm::vec3> albedo(size_t(elements.leaf_count()));
  std::vector<int> tag(size_t(elements.leaf_count()));
  for (int leaf = 0; leaf < elements.leaf_count(); ++leaf) {
    const int m = materials[size_t(elements.instance_of_leaf[size_t(leaf)])];
    albedo[size_t(leaf)] = MaterialAlbedo(state, m);
    tag[size_t(leaf)] = m;
  }
  return PatchesFromElements(elements, albedo, tag);
}

}  // namespace gistream::antiradiance
