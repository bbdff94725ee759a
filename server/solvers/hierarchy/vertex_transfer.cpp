#include "solvers/hierarchy/vertex_transfer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scene/proxies/surface_distance.h"
#include "util/parallel_for.h"

namespace gistream::hierarchy {
namespace {

constexpr int kMaxDim = 128;  // cells per axis
// A triangle faces a vertex's side when their normals are within 60
// degrees: a proxy bends a surface by far less, and a perpendicular face
// (a box's next wall in the same primitive) is another surface.
constexpr float kFacing = 0.5f;

// Triangles of `mesh` binned by their bounding boxes into a uniform grid.
class TriangleBins {
 public:
  explicit TriangleBins(const Primitive& mesh) : mesh_(mesh) {
    const size_t triangles = mesh.indices.size() / 3;
    for (const glm::vec3& p : mesh.positions) bounds_.Extend(p);
    if (triangles == 0 || bounds_.empty()) return;
    const glm::vec3 extent = bounds_.max - bounds_.min;
    const float widest = std::max({extent.x, extent.y, extent.z});
    // About one triangle per cell on a surface: side ~ widest / sqrt(triangles).
    cell_ = std::max(widest / std::sqrt(float(triangles)), widest / float(kMaxDim));
    if (!(cell_ > 0.0f)) cell_ = 1.0f;
    dims_ = glm::clamp(glm::ivec3(extent / cell_) + 1, glm::ivec3(1), glm::ivec3(kMaxDim));
    const size_t cells = size_t(dims_.x) * size_t(dims_.y) * size_t(dims_.z);
    start_.assign(cells + 1, 0);
    auto each_cell = [&](size_t t, auto&& f) {
      glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
      for (size_t k = 0; k < 3; ++k) {
        const glm::vec3& p = mesh.positions[mesh.indices[3 * t + k]];
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
      const glm::ivec3 a = Cell(lo), b = Cell(hi);
      for (int z = a.z; z <= b.z; ++z)
        for (int y = a.y; y <= b.y; ++y)
          for (int x = a.x; x <= b.x; ++x) f(Index({x, y, z}));
    };
    for (size_t t = 0; t < triangles; ++t) each_cell(t, [&](size_t c) { ++start_[c + 1]; });
    for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
    tris_.resize(start_[cells]);
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (size_t t = 0; t < triangles; ++t)
      each_cell(t, [&](size_t c) { tris_[fill[c]++] = uint32_t(t); });
  }

  // The nearest triangle to p whose side agrees with `normal` (any when
  // `facing` is false), and the nearest point on it; false when none.
  bool Nearest(const glm::vec3& p, const glm::vec3& normal, bool facing, uint32_t* triangle,
               glm::vec3* point) const {
    if (tris_.empty()) return false;
    const glm::ivec3 c = Cell(p);
    // p (or, outside the grid, its clamped cell) is at least r cells away
    // from every cell outside the (2r+1)^3 block around its cell.
    float best = std::numeric_limits<float>::max();
    const int rings = std::max({dims_.x, dims_.y, dims_.z});
    for (int r = 0; r <= rings; ++r) {
      for (int z = c.z - r; z <= c.z + r; ++z)
        for (int y = c.y - r; y <= c.y + r; ++y)
          for (int x = c.x - r; x <= c.x + r; ++x) {
            if (std::max({std::abs(x - c.x), std::abs(y - c.y), std::abs(z - c.z)}) != r) continue;
            if (x < 0 || y < 0 || z < 0 || x >= dims_.x || y >= dims_.y || z >= dims_.z) continue;
            const size_t cell = Index({x, y, z});
            for (uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
              const uint32_t t = tris_[k];
              if (facing && !(glm::dot(TriangleNormal(t), normal) >= kFacing)) continue;
              const glm::vec3 q =
                  ClosestPointOnTriangle(p, Corner(t, 0), Corner(t, 1), Corner(t, 2));
              const float d = glm::length(q - p);
              if (d < best) {
                best = d;
                *triangle = t;
                *point = q;
              }
            }
          }
      // Every triangle not yet seen lies at least r cells away.
      if (best <= float(r) * cell_) return true;
    }
    return best < std::numeric_limits<float>::max();
  }

  const glm::vec3& Corner(uint32_t t, int k) const {
    return mesh_.positions[mesh_.indices[3 * size_t(t) + size_t(k)]];
  }

 private:
  glm::ivec3 Cell(const glm::vec3& p) const {
    return glm::clamp(glm::ivec3(glm::floor((p - bounds_.min) / cell_)), glm::ivec3(0), dims_ - 1);
  }
  size_t Index(const glm::ivec3& c) const {
    return (size_t(c.z) * size_t(dims_.y) + size_t(c.y)) * size_t(dims_.x) + size_t(c.x);
  }
  // The side a triangle's elements face (unit): its vertex normals
  // summed, or its winding when it has none.
  glm::vec3 TriangleNormal(uint32_t t) const {
    glm::vec3 n(0.0f);
    if (mesh_.normals.size() == mesh_.positions.size()) {
      for (size_t k = 0; k < 3; ++k) n += mesh_.normals[mesh_.indices[3 * size_t(t) + k]];
    }
    if (!(glm::dot(n, n) > 0.0f))
      n = glm::cross(Corner(t, 1) - Corner(t, 0), Corner(t, 2) - Corner(t, 0));
    const float len = glm::length(n);
    return len > 0.0f ? n / len : n;
  }

  const Primitive& mesh_;
  Bounds bounds_;
  float cell_ = 1.0f;
  glm::ivec3 dims_{1};
  std::vector<uint32_t> start_;  // CSR: triangles of cell c are
  std::vector<uint32_t> tris_;   // tris_[start_[c] .. start_[c + 1])
};

// Barycentrics of q (a point of triangle a, b, c) by areas; along the
// longest side for a degenerate triangle.
glm::vec3 Barycentrics(const glm::vec3& q, const glm::vec3& a, const glm::vec3& b,
                       const glm::vec3& c) {
  const glm::vec3 n = glm::cross(b - a, c - a);
  const float area2 = glm::dot(n, n);
  if (!(area2 > 0.0f) || !std::isfinite(area2)) {
    // A segment (or a point): q's parameter on the longest side.
    const glm::vec3 p[3] = {a, b, c};
    int i = 0, j = 1;
    float longest = -1.0f;
    for (int u = 0; u < 3; ++u) {
      const int v = (u + 1) % 3;
      const float d = glm::dot(p[v] - p[u], p[v] - p[u]);
      if (d > longest) longest = d, i = u, j = v;
    }
    glm::vec3 w(0.0f);
    const float t =
        longest > 0.0f ? std::clamp(glm::dot(q - p[i], p[j] - p[i]) / longest, 0.0f, 1.0f) : 0.0f;
    w[i] = 1.0f - t;
    w[j] += t;
    return w;
  }
  glm::vec3 w(glm::dot(glm::cross(b - q, c - q), n), glm::dot(glm::cross(c - q, a - q), n),
              glm::dot(glm::cross(a - q, b - q), n));
  w = glm::max(w / area2, glm::vec3(0.0f));
  const float sum = w.x + w.y + w.z;
  return sum > 0.0f ? w / sum : glm::vec3(1.0f, 0.0f, 0.0f);
}

}  // namespace

VertexTransfer TransferVertices(const Primitive& to, const Primitive& from) {
  VertexTransfer out;
  const size_t n = to.positions.size();
  out.corner.assign(n, glm::uvec3(0));
  out.weight.assign(n, glm::vec3(0.0f));
  const TriangleBins bins(from);
  const bool has_normals = to.normals.size() == n;
  ParallelFor(n, 1024, [&](size_t v) {
    const glm::vec3& p = to.positions[v];
    glm::vec3 normal = has_normals ? to.normals[v] : glm::vec3(0.0f);
    const float len = glm::length(normal);
    const bool facing = len > 0.0f && std::isfinite(len);
    if (facing) normal /= len;
    uint32_t t = 0;
    glm::vec3 q(0.0f);
    if (!bins.Nearest(p, normal, facing, &t, &q) &&
        !(facing && bins.Nearest(p, normal, false, &t, &q))) {
      return;
    }
    out.corner[v] = glm::uvec3(from.indices[3 * size_t(t)], from.indices[3 * size_t(t) + 1],
                               from.indices[3 * size_t(t) + 2]);
    out.weight[v] = Barycentrics(q, bins.Corner(t, 0), bins.Corner(t, 1), bins.Corner(t, 2));
  });
  return out;
}

}  // namespace gistream::hierarchy
