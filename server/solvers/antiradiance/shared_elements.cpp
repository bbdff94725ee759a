#include "solvers/antiradiance/shared_elements.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <utility>

#include "solvers/antiradiance/near_field.h"
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

// Long edges subdivided to the scene-sized limit `max_edge`
// (hierarchy/subdivide.h), of proxy level `level` when >= 0 (the coarsest
// within a tenth of it, hierarchy/element_source.h), and near a
// double-sided emitter to its distance (near_field.h); then surfels, their
// hierarchy and cells.
SurfelMesh BuildSurfelMesh(const Primitive& full, int level, float max_edge,
                           const NearFieldLimit& near) {
  Primitive proxy;
  if (level >= 0) proxy = hierarchy::ProxyLevelMesh(full, level);
  const Primitive& source = level < 0 ? full : proxy;
  const float limit2 = max_edge > 0.0f && std::isfinite(max_edge)
                           ? max_edge * max_edge
                           : std::numeric_limits<float>::infinity();
  const Primitive subdivided =
      hierarchy::SubdivideEdges(source, [&near, limit2](const glm::vec3& a, const glm::vec3& b) {
        const glm::vec3 e = a - b;
        return glm::dot(e, e) > limit2 || (!near.empty() && near.TooLong(a, b));
      });
  auto mesh = std::make_shared<hierarchy::ElementMesh>();
  mesh->surfels = hierarchy::CreateSurfels(subdivided);
  mesh->tree = hierarchy::CreateHierarchy(mesh->surfels);
  SurfelMesh out;
  out.cells = VertexCells(subdivided);
  out.elements = std::move(mesh);
  return out;
}

Patches SurfelPatches(const SceneState& state, const GpuScene& gpu, SurfelCache& meshes,
                      bool full_detail) {
  std::vector<hierarchy::ElementInstance> instances;
  std::vector<glm::mat4> world;
  std::vector<int> materials;
  std::vector<const std::vector<std::vector<CellQuad>>*> cells_of_instance;
  // Each cache key's instances, for the near-field test (near_field.h).
  const auto key_of = [&state](const DrawItem& d) {
    return std::pair(state.Deforms(size_t(d.node)) ? -1 - d.node : d.mesh, d.primitive);
  };
  const std::vector<NearSheet> sheets = DoubleSidedEmitters(state, gpu);
  std::map<std::pair<int, int>, std::vector<glm::mat4>> placements;
  if (!sheets.empty()) {
    for (const DrawItem& d : gpu.draws())
      placements[key_of(d)].push_back(state.world()[size_t(d.node)]);
  }
  const float world_max_edge = WorldMaxEdge(state, gpu);
  std::map<std::pair<int, int>, NearFieldLimit> limits;  // once per key
  for (const DrawItem& d : gpu.draws()) {
    // A deforming instance's surfels follow its posed mesh: its own entry,
    // rebuilt every time.
    const bool deforms = state.Deforms(size_t(d.node));
    SurfelMesh& cached = meshes[key_of(d)];
    const Primitive& full = state.NodeMesh(size_t(d.node)).primitives[size_t(d.primitive)];
    auto [it, fresh] = limits.try_emplace(key_of(d));
    if (fresh && !sheets.empty()) {
      it->second = NearFieldLimit(sheets, d.mesh, d.primitive, full.bounds, placements[key_of(d)],
                                  world_max_edge);
    }
    const NearFieldLimit& near = it->second;
    std::vector<float> near_key = near.Key();
    if (!cached.elements || deforms || cached.near_key != near_key) {
      const float max_edge = hierarchy::LocalMaxEdge(state, gpu, d.mesh, d.primitive);
      const int level = hierarchy::ElementLevel(full, max_edge, full_detail || deforms);
      cached = BuildSurfelMesh(full, level, max_edge, near);
      cached.near_key = std::move(near_key);
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
