#include "solvers/antiradiance/shared_elements.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <utility>

#include "solvers/antiradiance/scene_patches.h"
#include "solvers/hierarchy/element_source.h"
#include "solvers/hierarchy/element_tree.h"
#include "solvers/hierarchy/subdivide.h"
#include "solvers/hierarchy/surfels.h"

namespace gistream::antiradiance {
namespace {

int Emit(const hierarchy::Elements& e, const std::vector<glm::vec3>& albedo,
         const std::vector<int>& tag, const std::vector<std::vector<CellQuad>>* cells, int node,
         Patches& out) {
  const int id = out.size();
  const size_t n = size_t(node);
  out.cell_begin.push_back(uint32_t(out.cell.size()));
  if (cells != nullptr && e.is_leaf(node) && n < cells->size()) {
    out.cell.insert(out.cell.end(), (*cells)[n].begin(), (*cells)[n].end());
  }
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
      const int child = Emit(e, albedo, tag, cells, c, out);
      out.children[size_t(id)][size_t(k++)] = child;
    }
  }
  return id;
}

}  // namespace

Patches PatchesFromElements(const hierarchy::Elements& elements,
                            const std::vector<glm::vec3>& leaf_albedo,
                            const std::vector<int>& leaf_tag,
                            const std::vector<std::vector<CellQuad>>* leaf_cells) {
  Patches out;
  for (int root : elements.roots())
    out.roots.push_back(Emit(elements, leaf_albedo, leaf_tag, leaf_cells, root, out));
  out.cell_begin.push_back(uint32_t(out.cell.size()));
  if (leaf_cells == nullptr) out.cell_begin.clear();
  return out;
}

std::vector<std::vector<CellQuad>> VertexCells(const Primitive& primitive) {
  // As hierarchy::CreateSurfels: the same triangles, the same thirds.
  const size_t n = primitive.positions.size();
  std::vector<std::vector<CellQuad>> cells(n);
  for (size_t i = 0; i + 2 < primitive.indices.size(); i += 3) {
    const uint32_t t[3] = {primitive.indices[i], primitive.indices[i + 1],
                           primitive.indices[i + 2]};
    if (t[0] >= n || t[1] >= n || t[2] >= n) continue;
    const glm::vec3 centroid =
        (primitive.positions[t[0]] + primitive.positions[t[1]] + primitive.positions[t[2]]) / 3.0f;
    if (!std::isfinite(centroid.x + centroid.y + centroid.z)) continue;
    for (int k = 0; k < 3; ++k) {
      const glm::vec3& v = primitive.positions[t[k]];
      const glm::vec3& q = primitive.positions[t[(k + 1) % 3]];
      const glm::vec3& r = primitive.positions[t[(k + 2) % 3]];
      cells[t[k]].push_back({v, 0.5f * (v + q), centroid, 0.5f * (v + r)});
    }
  }
  return cells;
}

Patches SurfelPatches(const SceneState& state, const GpuScene& gpu, SurfelCache& meshes,
                      bool full_detail) {
  std::vector<hierarchy::ElementInstance> instances;
  std::vector<glm::mat4> world;
  std::vector<int> materials;
  std::vector<const std::vector<std::vector<CellQuad>>*> cells_of_instance;
  for (const DrawItem& d : gpu.draws()) {
    // A deforming instance's surfels follow its posed mesh: its own entry,
    // rebuilt every time.
    const bool deforms = state.Deforms(size_t(d.node));
    SurfelMesh& cached = meshes[{deforms ? -1 - d.node : d.mesh, d.primitive}];
    if (!cached.elements || deforms) {
      auto mesh = std::make_shared<hierarchy::ElementMesh>();
      // Long edges subdivided to the scene-sized limit (hierarchy/subdivide.h),
      // of the coarsest proxy level within a tenth of it when there is one
      // (hierarchy/element_source.h; deforming primitives have none).
      const Primitive& full = state.NodeMesh(size_t(d.node)).primitives[size_t(d.primitive)];
      const float max_edge = hierarchy::LocalMaxEdge(state, gpu, d.mesh, d.primitive);
      const int level = hierarchy::ElementLevel(full, max_edge, full_detail || deforms);
      const Primitive subdivided =
          level < 0
              ? hierarchy::SubdivideLongEdges(full, max_edge)
              : hierarchy::SubdivideLongEdges(hierarchy::ProxyLevelMesh(full, level), max_edge);
      mesh->surfels = hierarchy::CreateSurfels(subdivided);
      mesh->tree = hierarchy::CreateHierarchy(mesh->surfels);
      cached.cells = VertexCells(subdivided);
      cached.elements = std::move(mesh);
    }
    instances.push_back({cached.elements, 0, {}});
    cells_of_instance.push_back(&cached.cells);
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
  // The cells in world space, per leaf (instance by instance, vertex order).
  std::vector<std::vector<CellQuad>> cells(size_t(elements.leaf_count()));
  for (size_t k = 0; k < elements.instances().size(); ++k) {
    const auto& local = *cells_of_instance[k];
    const int offset = elements.instances()[k].leaf_offset;
    for (size_t v = 0; v < local.size() && offset + int(v) < elements.leaf_count(); ++v) {
      auto& out = cells[size_t(offset) + v];
      for (const CellQuad& q : local[v]) {
        CellQuad w;
        for (size_t c = 0; c < q.size(); ++c) w[c] = glm::vec3(world[k] * glm::vec4(q[c], 1.0f));
        out.push_back(w);
      }
    }
  }
  return PatchesFromElements(elements, albedo, tag, &cells);
}

}  // namespace gistream::antiradiance
