#include "solvers/antiradiance/near_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "solvers/hierarchy/element_source.h"
#include "solvers/hierarchy/subdivide.h"

namespace gistream::antiradiance {
namespace {

// Distances to a sheet's box's surface, which stands for the sheet: from
// outside, to the box; from inside (an emitter enclosing the scene, a
// sky box), to its nearest face, so what it encloses is not all near it.
float Distance(const glm::vec3& p, const Bounds& b) {
  const glm::vec3 outside = glm::max(glm::max(b.min - p, p - b.max), glm::vec3(0.0f));
  if (outside != glm::vec3(0.0f)) return glm::length(outside);
  const glm::vec3 inside = glm::min(p - b.min, b.max - p);
  return std::min({inside.x, inside.y, inside.z});
}

// A lower bound on Distance over the points of box `a`.
float Distance(const Bounds& a, const Bounds& b) {
  const glm::vec3 gap = glm::max(glm::max(a.min - b.max, b.min - a.max), glm::vec3(0.0f));
  if (gap != glm::vec3(0.0f)) return glm::length(gap);
  const glm::vec3 lo = a.min - b.min, hi = b.max - a.max;
  if (glm::any(glm::lessThan(lo, glm::vec3(0.0f))) || glm::any(glm::lessThan(hi, glm::vec3(0.0f))))
    return 0.0f;  // straddles the box's surface
  const glm::vec3 inside = glm::min(lo, hi);
  return std::min({inside.x, inside.y, inside.z});
}

// The sheets within reach of `box` (world), of other primitives than
// (mesh, primitive).
std::vector<Bounds> SheetsNear(const std::vector<NearSheet>& sheets, int mesh, int primitive,
                               const Bounds& box, float world_max_edge) {
  std::vector<Bounds> out;
  for (const NearSheet& s : sheets) {
    if (s.mesh == mesh && s.primitive == primitive) continue;
    if (NearFieldEdgeAt(Distance(box, s.box), world_max_edge) < world_max_edge)
      out.push_back(s.box);
  }
  return out;
}

}  // namespace

float WorldMaxEdge(const SceneState& state, const GpuScene& gpu) {
  const Bounds bounds = gpu.WorldBounds(state);
  if (bounds.empty()) return 0.0f;
  const float edge = hierarchy::kMaxElementEdge * glm::length(bounds.extent());
  return std::isfinite(edge) ? edge : 0.0f;
}

float NearFieldEdgeAt(float d, float world_max_edge) {
  return std::max(kNearFieldEdge * d, kNearFieldFloor * world_max_edge);
}

std::vector<NearSheet> DoubleSidedEmitters(const SceneState& state, const GpuScene& gpu) {
  std::vector<NearSheet> out;
  const std::vector<Material>& materials = state.materials();
  for (const DrawItem& d : gpu.draws()) {
    if (d.material < 0 || size_t(d.material) >= materials.size()) continue;
    const Material& m = materials[size_t(d.material)];
    if (!m.double_sided || !m.emissive()) continue;
    const Primitive& p = state.NodeMesh(size_t(d.node)).primitives[size_t(d.primitive)];
    const Bounds box = p.bounds.Transformed(state.world()[size_t(d.node)]);
    if (!box.empty()) out.push_back({box, d.mesh, d.primitive});
  }
  return out;
}

NearFieldLimit::NearFieldLimit(const std::vector<NearSheet>& sheets, int mesh, int primitive,
                               const Bounds& local_bounds, const std::vector<glm::mat4>& world,
                               float world_max_edge)
    : world_max_edge_(world_max_edge) {
  if (sheets.empty() || !(world_max_edge > 0.0f)) return;
  for (const glm::mat4& m : world) {
    const std::vector<Bounds> near =
        SheetsNear(sheets, mesh, primitive, local_bounds.Transformed(m), world_max_edge);
    if (near.empty()) continue;
    world_.push_back(m);
    for (const Bounds& b : near) {
      if (std::find_if(sheets_.begin(), sheets_.end(), [&b](const Bounds& o) {
            return o.min == b.min && o.max == b.max;
          }) == sheets_.end())
        sheets_.push_back(b);
    }
  }
}

bool NearFieldLimit::TooLong(const glm::vec3& a, const glm::vec3& b) const {
  const float floor = kNearFieldFloor * world_max_edge_;
  for (const glm::mat4& m : world_) {
    const glm::vec3 wa = glm::vec3(m * glm::vec4(a, 1.0f));
    const glm::vec3 wb = glm::vec3(m * glm::vec4(b, 1.0f));
    const float length = glm::length(wa - wb);
    if (!(length > floor)) continue;
    const glm::vec3 mid = 0.5f * (wa + wb);
    for (const Bounds& s : sheets_)
      if (length > kNearFieldEdge * Distance(mid, s)) return true;
  }
  return false;
}

double NearFieldLimit::SplitRatio(const glm::vec3& a, const glm::vec3& b,
                                  const glm::vec3& c) const {
  double ratio = 0.0;
  for (const glm::mat4& m : world_) {
    const glm::vec3 w[3] = {glm::vec3(m * glm::vec4(a, 1.0f)), glm::vec3(m * glm::vec4(b, 1.0f)),
                            glm::vec3(m * glm::vec4(c, 1.0f))};
    Bounds box;
    for (const glm::vec3& v : w) box.Extend(v);
    const float longest =
        std::max({glm::length(w[1] - w[0]), glm::length(w[2] - w[1]), glm::length(w[0] - w[2])});
    // Every edge's midpoint lies in the box: no farther from a sheet.
    float d_min = std::numeric_limits<float>::max();
    for (const Bounds& s : sheets_) d_min = std::min(d_min, Distance(box, s));
    if (std::isfinite(longest))
      ratio = std::max(ratio, double(longest) / double(NearFieldEdgeAt(d_min, world_max_edge_)));
  }
  return ratio;
}

std::vector<float> NearFieldLimit::Key() const {
  std::vector<float> key;
  for (const Bounds& s : sheets_)
    key.insert(key.end(), {s.min.x, s.min.y, s.min.z, s.max.x, s.max.y, s.max.z});
  for (const glm::mat4& m : world_)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) key.push_back(m[c][r]);
  return key;
}

uint64_t NearFieldVertexBound(const SceneState& state, const GpuScene& gpu, bool full_detail) {
  const std::vector<NearSheet> sheets = DoubleSidedEmitters(state, gpu);
  const float world_max_edge = WorldMaxEdge(state, gpu);
  if (sheets.empty() || !(world_max_edge > 0.0f)) return 0;
  // Per refined mesh, as SurfelPatches caches them: (mesh, primitive), a
  // deforming node's its own. Its refinement serves every instance.
  std::map<std::pair<int, int>, std::vector<const DrawItem*>> draws_of;
  for (const DrawItem& d : gpu.draws())
    draws_of[{state.Deforms(size_t(d.node)) ? -1 - d.node : d.mesh, d.primitive}].push_back(&d);
  uint64_t vertices = 0;
  for (const auto& [key, draws] : draws_of) {
    const DrawItem& d = *draws.front();
    const Primitive& p = state.NodeMesh(size_t(d.node)).primitives[size_t(d.primitive)];
    std::vector<glm::mat4> world;
    for (const DrawItem* e : draws) world.push_back(state.world()[size_t(e->node)]);
    const NearFieldLimit near(sheets, d.mesh, d.primitive, p.bounds, world, world_max_edge);
    if (near.empty()) continue;
    // The mesh the elements are made of, as SubdividedVertexBound takes it.
    const float max_edge = hierarchy::LocalMaxEdge(state, gpu, d.mesh, d.primitive);
    const int level =
        hierarchy::ElementLevel(p, max_edge, full_detail || state.Deforms(size_t(d.node)));
    const std::vector<uint32_t>& indices =
        level >= 0 ? p.proxies[size_t(level)].indices : p.indices;
    uint64_t added = 0;
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
      if (indices[t] >= p.positions.size() || indices[t + 1] >= p.positions.size() ||
          indices[t + 2] >= p.positions.size())
        continue;
      const double ratio = near.SplitRatio(p.positions[indices[t]], p.positions[indices[t + 1]],
                                           p.positions[indices[t + 2]]);
      if (!(ratio > 1.0)) continue;
      // Midpoint splits halve edges: 2^k segments, 2^k >= the ratio.
      const double n = std::min(std::exp2(std::ceil(std::log2(ratio))), double(1 << 20));
      added += uint64_t((n + 1.0) * (n + 2.0) / 2.0);
    }
    // Every instance, twice on a doubleSided material (its mirrored leaves,
    // patches.h: AddBackFaces).
    for (const DrawItem* e : draws) {
      const bool twice = e->material >= 0 && size_t(e->material) < state.materials().size() &&
                         state.materials()[size_t(e->material)].double_sided;
      vertices += (twice ? 2 : 1) * added;
    }
  }
  return vertices;
}

}  // namespace gistream::antiradiance
