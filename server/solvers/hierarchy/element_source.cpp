#include "solvers/hierarchy/element_source.h"

#include <cmath>
#include <algorithm>
#include <limits>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "scene/proxies/proxy_levels.h"

namespace gistream::hierarchy {
namespace {

constexpr int kMaxFlipPasses = 64;
// Two triangles count as coplanar when the fourth corner lies within this
// fraction of the shared edge's length off the first one's plane: a flip
// then leaves the surface where it was.
constexpr float kCoplanar = 1e-5f;

// The angle at c in triangle (a, b, c).
float AngleAt(const glm::vec3& c, const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 u = a - c, v = b - c;
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

// Edge flips towards the Delaunay triangulation within coplanar regions:
// an edge ab between (a, b, c) and (b, a, d) becomes cd when the angles
// opposite it sum to more than pi and both new triangles keep the
// orientation. A simplifier's flat regions are fans of slivers; their
// vertex discs have little area while the triangles reach far, so the
// display interpolates a corner's irradiance across the sliver and a
// splat of 1.5 disc radii leaves holes. Flips never change a coplanar
// region's surface, so the level's recorded error still holds.
void FlipToDelaunay(Primitive& mesh) {
  std::vector<uint32_t>& idx = mesh.indices;
  const size_t triangles = idx.size() / 3;
  const auto& p = mesh.positions;
  for (int pass = 0; pass < kMaxFlipPasses; ++pass) {
    std::map<std::pair<uint32_t, uint32_t>, std::vector<std::pair<size_t, int>>> edges;
    for (size_t t = 0; t < triangles; ++t)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = idx[3 * t + size_t(k)], b = idx[3 * t + size_t((k + 1) % 3)];
        edges[std::minmax(a, b)].push_back({t, k});
      }
    std::vector<bool> touched(triangles, false);
    int flips = 0;
    for (const auto& [key, uses] : edges) {
      if (uses.size() != 2) continue;
      const auto [t1, k1] = uses[0];
      const auto [t2, k2] = uses[1];
      if (touched[t1] || touched[t2] || t1 == t2) continue;
      const uint32_t a = idx[3 * t1 + size_t(k1)], b = idx[3 * t1 + size_t((k1 + 1) % 3)];
      const uint32_t c = idx[3 * t1 + size_t((k1 + 2) % 3)];
      // The other triangle must run b -> a (consistent winding).
      if (idx[3 * t2 + size_t(k2)] != b || idx[3 * t2 + size_t((k2 + 1) % 3)] != a) continue;
      const uint32_t d = idx[3 * t2 + size_t((k2 + 2) % 3)];
      if (c == d) continue;
      const glm::vec3 n = glm::cross(p[b] - p[a], p[c] - p[a]);
      const float n_len = glm::length(n), ab = glm::length(p[b] - p[a]);
      if (!(n_len > 0.0f) || !(ab > 0.0f)) continue;
      if (std::abs(glm::dot(p[d] - p[a], n / n_len)) > kCoplanar * ab) continue;
      if (AngleAt(p[c], p[a], p[b]) + AngleAt(p[d], p[a], p[b]) <= 3.14159265f + 1e-5f) continue;
      // New triangles (a, d, c) and (d, b, c): both must face along n.
      if (glm::dot(glm::cross(p[d] - p[a], p[c] - p[a]), n) <= 0.0f ||
          glm::dot(glm::cross(p[b] - p[d], p[c] - p[d]), n) <= 0.0f)
        continue;
      const auto it = edges.find(std::minmax(c, d));
      if (it != edges.end()) continue;  // cd is an edge already: a flip would duplicate it
      idx[3 * t1] = a, idx[3 * t1 + 1] = d, idx[3 * t1 + 2] = c;
      idx[3 * t2] = d, idx[3 * t2 + 1] = b, idx[3 * t2 + 2] = c;
      touched[t1] = touched[t2] = true;
      ++flips;
    }
    if (flips == 0) break;
  }
}

}  // namespace

int ElementLevel(const Primitive& primitive, float max_edge, bool full_detail) {
  if (full_detail || !(max_edge > 0.0f) || !std::isfinite(max_edge)) return -1;
  if (primitive.indices.size() / 3 < kMinProxyTriangles) return -1;
  return PickProxyLevel(std::span<const ProxyLevel>(primitive.proxies), 1.0f,
                        kProxyErrorFraction * max_edge);
}

Primitive ProxyLevelMesh(const Primitive& primitive, int level) {
  Primitive out;
  out.material = primitive.material;
  if (level < 0 || size_t(level) >= primitive.proxies.size()) return out;
  const std::vector<uint32_t>& indices = primitive.proxies[size_t(level)].indices;
  const size_t n = primitive.positions.size();
  constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> remap(n, kUnused);
  for (uint32_t v : indices) {
    if (v < n) remap[v] = 0;
  }
  const bool has_normals = primitive.normals.size() == n;
  const bool has_uvs = primitive.uvs.size() == n;
  for (size_t v = 0; v < n; ++v) {
    if (remap[v] == kUnused) continue;
    remap[v] = uint32_t(out.positions.size());
    out.positions.push_back(primitive.positions[v]);
    if (has_normals) out.normals.push_back(primitive.normals[v]);
    if (has_uvs) out.uvs.push_back(primitive.uvs[v]);
    out.bounds.Extend(primitive.positions[v]);
  }
  out.indices.reserve(indices.size());
  for (size_t i = 0; i + 2 < indices.size(); i += 3) {
    if (indices[i] >= n || indices[i + 1] >= n || indices[i + 2] >= n) continue;
    for (size_t k = 0; k < 3; ++k) out.indices.push_back(remap[indices[i + k]]);
  }
  FlipToDelaunay(out);
  return out;
}

Primitive SurfaceOf(const Primitive& primitive) {
  Primitive out;
  out.positions = primitive.positions;
  out.normals = primitive.normals;
  out.uvs = primitive.uvs;
  out.indices = primitive.indices;
  out.material = primitive.material;
  out.bounds = primitive.bounds;
  return out;
}

}  // namespace gistream::hierarchy
