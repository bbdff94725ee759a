#include "solvers/hierarchy/subdivide.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace gistream::hierarchy {
namespace {

// Bounds the work on a pathological input (a huge triangle in a tiny
// scene): passes and vertices.
constexpr int kMaxPasses = 16;
constexpr size_t kMaxVertices = size_t(1) << 21;

}  // namespace

Primitive SubdivideLongEdges(const Primitive& primitive, float max_edge) {
  Primitive out = primitive;
  if (!(max_edge > 0.0f) || !std::isfinite(max_edge)) return out;
  const float limit2 = max_edge * max_edge;
  const bool has_normals = out.normals.size() == out.positions.size();
  const bool has_uvs = out.uvs.size() == out.positions.size();
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    const size_t n = out.positions.size();
    auto too_long = [&](uint32_t a, uint32_t b) {
      const glm::vec3 d = out.positions[a] - out.positions[b];
      return glm::dot(d, d) > limit2;
    };
    // One midpoint per long edge, shared by the triangles on both sides.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
    auto mid = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = midpoint.try_emplace({key.first, key.second}, uint32_t(out.positions.size()));
      if (inserted) {
        out.positions.push_back(0.5f * (out.positions[a] + out.positions[b]));
        if (has_normals) {
          const glm::vec3 s = out.normals[a] + out.normals[b];
          const float len = glm::length(s);
          out.normals.push_back(len > 0.0f ? s / len : out.normals[a]);
        }
        if (has_uvs) out.uvs.push_back(0.5f * (out.uvs[a] + out.uvs[b]));
      }
      return it->second;
    };
    std::vector<uint32_t> indices;
    indices.reserve(out.indices.size() * 2);
    bool split = false;
    for (size_t i = 0; i + 2 < out.indices.size(); i += 3) {
      std::array<uint32_t, 3> t = {out.indices[i], out.indices[i + 1], out.indices[i + 2]};
      if (t[0] >= n || t[1] >= n || t[2] >= n) continue;
      // Edge k runs from t[k] to t[k + 1].
      std::array<bool, 3> cut{};
      int cuts = 0;
      for (int k = 0; k < 3; ++k) cuts += (cut[size_t(k)] = too_long(t[size_t(k)], t[size_t((k + 1) % 3)])) ? 1 : 0;
      if (cuts == 0) {
        indices.insert(indices.end(), t.begin(), t.end());
        continue;
      }
      split = true;
      if (cuts == 3) {
        const uint32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
        indices.insert(indices.end(), {t[0], ab, ca, ab, t[1], bc, ca, bc, t[2], ab, bc, ca});
        continue;
      }
      // Rotate (winding kept) so that the cut edges come first: one cut is
      // edge ab, two are ab and bc.
      int r = 0;
      if (cuts == 1) {
        while (!cut[size_t(r)]) ++r;  // the cut edge
      } else {
        while (cut[size_t(r)]) ++r;  // the edge left whole becomes ca
        r = (r + 1) % 3;
      }
      const uint32_t a = t[size_t(r)], b = t[size_t((r + 1) % 3)], c = t[size_t((r + 2) % 3)];
      const uint32_t ab = mid(a, b);
      if (cuts == 1) {
        indices.insert(indices.end(), {a, ab, c, ab, b, c});
      } else {
        const uint32_t bc = mid(b, c);
        indices.insert(indices.end(), {ab, b, bc, a, ab, bc, a, bc, c});
      }
    }
    out.indices = std::move(indices);
    if (!split || out.positions.size() > kMaxVertices) break;
  }
  return out;
}

float LocalMaxEdge(const SceneState& state, const GpuScene& gpu, int mesh, int primitive) {
  const Bounds bounds = gpu.WorldBounds(state);
  const float diagonal = glm::length(bounds.max - bounds.min);
  float scale = 0.0f;
  for (const DrawItem& d : gpu.draws()) {
    if (d.mesh != mesh || d.primitive != primitive) continue;
    const glm::mat4& m = state.world()[size_t(d.node)];
    for (int k = 0; k < 3; ++k) scale = std::max(scale, glm::length(glm::vec3(m[k])));
  }
  if (bounds.empty() || !(diagonal > 0.0f) || !(scale > 0.0f) || !std::isfinite(diagonal / scale)) return 0.0f;
  return kMaxElementEdge * diagonal / scale;
}

}  // namespace gistream::hierarchy
