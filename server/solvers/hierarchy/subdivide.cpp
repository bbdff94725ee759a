#include "solvers/hierarchy/subdivide.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "solvers/hierarchy/element_source.h"

namespace gistream::hierarchy {
namespace {

// Bounds the work on a pathological input (a huge triangle in a tiny
// scene): passes and vertices.
constexpr int kMaxPasses = 16;
constexpr size_t kMaxVertices = size_t(1) << 21;

}  // namespace

namespace {

// The unit sum of two normals (the first when they cancel): a midpoint's.
glm::vec3 MidNormal(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 s = a + b;
  const float len = glm::length(s);
  return len > 0.0f ? s / len : a;
}

}  // namespace

Primitive SubdivideLongEdges(const Primitive& primitive, float max_edge, Midpoints* midpoints) {
  if (!(max_edge > 0.0f) || !std::isfinite(max_edge)) {
    if (midpoints) midpoints->clear();
    return primitive;
  }
  const float limit2 = max_edge * max_edge;
  return SubdivideEdges(
      primitive,
      [limit2](const glm::vec3& a, const glm::vec3& b) {
        const glm::vec3 d = a - b;
        return glm::dot(d, d) > limit2;
      },
      midpoints);
}

Primitive SubdivideEdges(const Primitive& primitive, const EdgeTest& edge_too_long,
                         Midpoints* midpoints) {
  if (midpoints) midpoints->clear();
  Primitive out = primitive;
  const bool has_normals = out.normals.size() == out.positions.size();
  const bool has_uvs = out.uvs.size() == out.positions.size();
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    const size_t n = out.positions.size();
    auto too_long = [&](uint32_t a, uint32_t b) {
      return edge_too_long(out.positions[a], out.positions[b]);
    };
    // One midpoint per long edge, shared by the triangles on both sides.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
    auto mid = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] =
          midpoint.try_emplace({key.first, key.second}, uint32_t(out.positions.size()));
      if (inserted) {
        out.positions.push_back(0.5f * (out.positions[a] + out.positions[b]));
        if (has_normals) out.normals.push_back(MidNormal(out.normals[a], out.normals[b]));
        if (has_uvs) out.uvs.push_back(0.5f * (out.uvs[a] + out.uvs[b]));
        if (midpoints) midpoints->push_back({a, b});
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
      for (int k = 0; k < 3; ++k)
        cuts += (cut[size_t(k)] = too_long(t[size_t(k)], t[size_t((k + 1) % 3)])) ? 1 : 0;
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

Primitive RepeatSubdivision(const Primitive& primitive, const Primitive& subdivided,
                            const Midpoints& midpoints) {
  Primitive out = subdivided;
  const size_t n = primitive.positions.size();
  if (n + midpoints.size() != subdivided.positions.size()) return out;  // not its subdivision
  const bool has_normals = out.normals.size() == out.positions.size() &&
                           primitive.normals.size() == primitive.positions.size();
  std::copy(primitive.positions.begin(), primitive.positions.end(), out.positions.begin());
  if (has_normals)
    std::copy(primitive.normals.begin(), primitive.normals.end(), out.normals.begin());
  for (size_t k = 0; k < midpoints.size(); ++k) {
    const auto [a, b] = midpoints[k];
    out.positions[n + k] = 0.5f * (out.positions[a] + out.positions[b]);
    if (has_normals) out.normals[n + k] = MidNormal(out.normals[a], out.normals[b]);
  }
  out.bounds = primitive.bounds;
  return out;
}

uint64_t SubdividedVertexBound(const SceneState& state, const GpuScene& gpu, bool full_detail,
                               bool double_sided_twice) {
  const Bounds bounds = gpu.WorldBounds(state);
  const float diagonal = glm::length(bounds.max - bounds.min);
  // The largest scale of each (mesh, primitive)'s instances, in one pass.
  std::map<std::pair<int, int>, float> scales;
  for (const DrawItem& d : gpu.draws()) {
    const glm::mat4& m = state.world()[size_t(d.node)];
    float& scale = scales[{d.mesh, d.primitive}];
    for (int k = 0; k < 3; ++k) scale = std::max(scale, glm::length(glm::vec3(m[k])));
  }
  const Scene& scene = state.scene();
  uint64_t vertices = 0;
  for (size_t ni = 0; ni < state.nodes().size(); ++ni) {
    const Node& node = state.nodes()[ni];
    if (node.mesh < 0 || size_t(node.mesh) >= scene.meshes.size()) continue;
    const Mesh& mesh = scene.meshes[size_t(node.mesh)];
    for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const Primitive& p = mesh.primitives[pi];
      const auto it = scales.find({node.mesh, int(pi)});
      const float scale = it == scales.end() ? 0.0f : it->second;
      const bool sized = !bounds.empty() && diagonal > 0.0f && scale > 0.0f;
      const float max_edge = sized ? kMaxElementEdge * diagonal / scale : 0.0f;
      // The mesh the elements are made of (element_source.h): a proxy
      // level where the builders take one, else the full mesh. Counting
      // the full mesh refused the 594K-triangle atrium at 24 GiB.
      const int level = ElementLevel(p, max_edge, full_detail || state.Deforms(ni));
      const std::vector<uint32_t>& indices =
          level >= 0 ? p.proxies[size_t(level)].indices : p.indices;
      const bool twice = double_sided_twice && p.material >= 0 &&
                         size_t(p.material) < state.materials().size() &&
                         state.materials()[size_t(p.material)].double_sided;
      const uint64_t copies = twice ? 2 : 1;
      vertices +=
          copies * (level >= 0 ? std::min(p.positions.size(), indices.size()) : p.positions.size());
      if (!(max_edge > 0.0f) || !std::isfinite(max_edge)) continue;
      for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        if (indices[t] >= p.positions.size() || indices[t + 1] >= p.positions.size() ||
            indices[t + 2] >= p.positions.size())
          continue;
        const glm::vec3& a = p.positions[indices[t]];
        const glm::vec3& b = p.positions[indices[t + 1]];
        const glm::vec3& c = p.positions[indices[t + 2]];
        const float longest =
            std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        if (!(longest > max_edge)) continue;
        // Midpoint splits halve edges: 2^k segments, 2^k >= longest / max_edge.
        const double n = std::min(
            std::exp2(std::ceil(std::log2(double(longest) / double(max_edge)))), double(1 << 20));
        vertices += copies * uint64_t((n + 1.0) * (n + 2.0) / 2.0);
      }
    }
  }
  return vertices;
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
  if (bounds.empty() || !(diagonal > 0.0f) || !(scale > 0.0f) || !std::isfinite(diagonal / scale))
    return 0.0f;
  return kMaxElementEdge * diagonal / scale;
}

}  // namespace gistream::hierarchy
