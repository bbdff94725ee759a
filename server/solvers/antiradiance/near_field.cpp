#include "solvers/antiradiance/near_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

// The scene-sized limit in world units (hierarchy::kMaxElementEdge).
float WorldMaxEdge(const SceneState& state, const GpuScene& gpu) {
  const Bounds bounds = gpu.WorldBounds(state);
  if (bounds.empty()) return 0.0f;
  const float edge = hierarchy::kMaxElementEdge * glm::length(bounds.extent());
  return std::isfinite(edge) ? edge : 0.0f;
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
                               const Bounds& local_bounds, std::vector<glm::mat4> world,
                               float world_max_edge)
    : world_(std::move(world)), floor_(kNearFieldFloor * world_max_edge) {
  if (!(world_max_edge > 0.0f)) return;
  for (const glm::mat4& m : world_) {
    for (const Bounds& b :
         SheetsNear(sheets, mesh, primitive, local_bounds.Transformed(m), world_max_edge)) {
      if (std::find_if(sheets_.begin(), sheets_.end(), [&b](const Bounds& o) {
            return o.min == b.min && o.max == b.max;
          }) == sheets_.end())
        sheets_.push_back(b);
    }
  }
  if (sheets_.empty()) world_.clear();
}

bool NearFieldLimit::TooLong(const glm::vec3& a, const glm::vec3& b) const {
  for (const glm::mat4& m : world_) {
    const glm::vec3 wa = glm::vec3(m * glm::vec4(a, 1.0f));
    const glm::vec3 wb = glm::vec3(m * glm::vec4(b, 1.0f));
    const float length = glm::length(wa - wb);
    if (!(length > floor_)) continue;
    const glm::vec3 mid = 0.5f * (wa + wb);
    for (const Bounds& s : sheets_)
      if (length > kNearFieldEdge * Distance(mid, s)) return true;
  }
  return false;
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
  uint64_t vertices = 0;
  for (const DrawItem& d : gpu.draws()) {
    const Primitive& p = state.NodeMesh(size_t(d.node)).primitives[size_t(d.primitive)];
    const glm::mat4& m = state.world()[size_t(d.node)];
    const std::vector<Bounds> near =
        SheetsNear(sheets, d.mesh, d.primitive, p.bounds.Transformed(m), world_max_edge);
    if (near.empty()) continue;
    // The mesh the elements are made of, as SubdividedVertexBound takes it.
    const float max_edge = hierarchy::LocalMaxEdge(state, gpu, d.mesh, d.primitive);
    const int level =
        hierarchy::ElementLevel(p, max_edge, full_detail || state.Deforms(size_t(d.node)));
    const std::vector<uint32_t>& indices =
        level >= 0 ? p.proxies[size_t(level)].indices : p.indices;
    // A doubleSided surface's leaves are mirrored (patches.h: AddBackFaces).
    const bool twice = d.material >= 0 && size_t(d.material) < state.materials().size() &&
                       state.materials()[size_t(d.material)].double_sided;
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
      if (indices[t] >= p.positions.size() || indices[t + 1] >= p.positions.size() ||
          indices[t + 2] >= p.positions.size())
        continue;
      Bounds box;
      float longest = 0.0f;
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 a = glm::vec3(m * glm::vec4(p.positions[indices[t + size_t(k)]], 1.0f));
        const glm::vec3 b =
            glm::vec3(m * glm::vec4(p.positions[indices[t + size_t((k + 1) % 3)]], 1.0f));
        box.Extend(a);
        longest = std::max(longest, glm::length(b - a));
      }
      float d_min = std::numeric_limits<float>::max();
      for (const Bounds& s : near) d_min = std::min(d_min, Distance(box, s));
      const float limit = NearFieldEdgeAt(d_min, world_max_edge);
      if (!(longest > limit) || !std::isfinite(longest)) continue;
      // Midpoint splits halve edges: 2^k segments, 2^k >= longest / limit.
      const double n = std::min(std::exp2(std::ceil(std::log2(double(longest) / double(limit)))),
                                double(1 << 20));
      vertices += (twice ? 2 : 1) * uint64_t((n + 1.0) * (n + 2.0) / 2.0);
    }
  }
  return vertices;
}

}  // namespace gistream::antiradiance
