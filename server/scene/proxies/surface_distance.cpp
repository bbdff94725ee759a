#include "scene/proxies/surface_distance.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>

#include "util/parallel_for.h"

namespace gistream {
namespace {

// At most this many cells (the CSR offsets stay a few MiB).
constexpr double kMaxCells = 1 << 21;

// Largest value seen, for non-negative floats (their bit patterns order as
// the values do).
void AtomicMax(std::atomic<uint32_t>& bits, float value) {
  uint32_t v;
  std::memcpy(&v, &value, sizeof(v));
  uint32_t seen = bits.load(std::memory_order_relaxed);
  while (v > seen && !bits.compare_exchange_weak(seen, v, std::memory_order_relaxed)) {
  }
}

float FloatOf(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof(f));
  return f;
}

// Calls fn(a, b, c, k, covering) for pieces that together cover triangle
// (a, b, c), each to be sampled on a barycentric k x k grid with
// sub-triangle edges <= `spacing` (k at most 256): every point of a
// sub-triangle lies within edge / sqrt(3) of one of its corners, the
// piece's covering radius. A piece within `spacing` or with an area of at
// least longest^2 / 8 is sampled as is; a thinner one is split at its
// longest edge's midpoint first (longest-edge bisection), so a sliver of
// length L costs about L / spacing samples, not (L / spacing)^2 / 2.
template <typename Fn>
void ForEachPiece(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, float spacing,
                  int depth, Fn&& fn) {
  const float ab = glm::length(b - a), bc = glm::length(c - b), ca = glm::length(a - c);
  const float longest = std::max({ab, bc, ca});
  const float twice_area = glm::length(glm::cross(b - a, c - a));
  if (longest <= spacing || 4.0f * twice_area >= longest * longest || depth >= 32) {
    const int k = std::clamp(int(std::ceil(longest / std::max(spacing, 1e-30f))), 1, 256);
    fn(a, b, c, k, longest / float(k) / std::sqrt(3.0f));
  } else if (ab == longest) {
    const glm::vec3 m = 0.5f * (a + b);
    ForEachPiece(a, m, c, spacing, depth + 1, fn);
    ForEachPiece(m, b, c, spacing, depth + 1, fn);
  } else if (bc == longest) {
    const glm::vec3 m = 0.5f * (b + c);
    ForEachPiece(a, b, m, spacing, depth + 1, fn);
    ForEachPiece(a, m, c, spacing, depth + 1, fn);
  } else {
    const glm::vec3 m = 0.5f * (c + a);
    ForEachPiece(a, b, m, spacing, depth + 1, fn);
    ForEachPiece(m, b, c, spacing, depth + 1, fn);
  }
}

}  // namespace

glm::vec3 ClosestPointOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                                 const glm::vec3& c) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const float denom = 1.0f / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

TriangleGrid::TriangleGrid(std::span<const glm::vec3> positions, std::span<const uint32_t> indices,
                           float cell)
    : positions_(positions), indices_(indices) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (uint32_t i : indices) {
    lo = glm::min(lo, positions[i]);
    hi = glm::max(hi, positions[i]);
  }
  if (indices.size() < 3) return;
  const glm::vec3 extent = glm::max(hi - lo, glm::vec3(0.0f));
  cell_ = std::max(cell, 1e-30f);
  const double volume =
      double(extent.x / cell_ + 1) * double(extent.y / cell_ + 1) * double(extent.z / cell_ + 1);
  if (volume > kMaxCells) cell_ *= float(std::cbrt(volume / kMaxCells)) * 1.01f;
  origin_ = lo;
  dims_ = glm::ivec3(glm::floor(extent / cell_)) + 1;
  const size_t cells = size_t(dims_.x) * size_t(dims_.y) * size_t(dims_.z);

  // Each triangle goes in every cell its box touches (two passes: count, fill).
  auto for_cells = [&](size_t t, auto&& fn) {
    const glm::vec3 &a = positions[indices[3 * t]], &b = positions[indices[3 * t + 1]],
                    &c = positions[indices[3 * t + 2]];
    const glm::ivec3 c0 =
        glm::clamp(glm::ivec3(glm::floor((glm::min(a, glm::min(b, c)) - origin_) / cell_)),
                   glm::ivec3(0), dims_ - 1);
    const glm::ivec3 c1 =
        glm::clamp(glm::ivec3(glm::floor((glm::max(a, glm::max(b, c)) - origin_) / cell_)),
                   glm::ivec3(0), dims_ - 1);
    for (int z = c0.z; z <= c1.z; ++z)
      for (int y = c0.y; y <= c1.y; ++y)
        for (int x = c0.x; x <= c1.x; ++x)
          fn((size_t(z) * size_t(dims_.y) + size_t(y)) * size_t(dims_.x) + size_t(x));
  };
  const size_t triangles = indices.size() / 3;
  cell_start_.assign(cells + 1, 0);
  for (size_t t = 0; t < triangles; ++t) for_cells(t, [&](size_t c) { ++cell_start_[c + 1]; });
  for (size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_tris_.resize(cell_start_[cells]);
  std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (size_t t = 0; t < triangles; ++t) {
    for_cells(t, [&](size_t c) { cell_tris_[fill[c]++] = uint32_t(t); });
  }
}

float TriangleGrid::Distance(const glm::vec3& p, float cap, float enough) const {
  if (cell_start_.empty()) return cap;
  const float enough2 = enough >= 0.0f ? enough * enough : -1.0f;
  const glm::ivec3 home = glm::ivec3(
      glm::clamp(glm::floor((p - origin_) / cell_), glm::vec3(0.0f), glm::vec3(dims_ - 1)));
  float best2 = cap * cap;
  // Shells of cells at Chebyshev distance r from `home`: a triangle in no
  // cell up to shell r is at least r cells away from p.
  const int max_r = int(std::ceil(cap / cell_)) + 1;
  for (int r = 0; r <= max_r; ++r) {
    // Triangles first met in shell r are at least (r - 1) cells from p.
    const float reach = float(r - 1) * cell_;
    if (r > 0 && reach * reach >= best2) break;
    const glm::ivec3 lo = home - r, hi = home + r;
    for (int z = std::max(lo.z, 0); z <= std::min(hi.z, dims_.z - 1); ++z) {
      for (int y = std::max(lo.y, 0); y <= std::min(hi.y, dims_.y - 1); ++y) {
        const bool inner_zy = z != lo.z && z != hi.z && y != lo.y && y != hi.y;
        for (int x = std::max(lo.x, 0); x <= std::min(hi.x, dims_.x - 1);
             x += (inner_zy && x == lo.x) ? 2 * r : 1) {
          const size_t c = (size_t(z) * size_t(dims_.y) + size_t(y)) * size_t(dims_.x) + size_t(x);
          for (uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
            const size_t t = cell_tris_[k];
            const glm::vec3 q = ClosestPointOnTriangle(p, positions_[indices_[3 * t]],
                                                       positions_[indices_[3 * t + 1]],
                                                       positions_[indices_[3 * t + 2]]);
            const glm::vec3 d = q - p;
            best2 = std::min(best2, glm::dot(d, d));
            if (best2 <= enough2) return std::sqrt(best2);
          }
        }
      }
    }
  }
  return std::min(std::sqrt(best2), cap);
}

float HausdorffBound(std::span<const glm::vec3> positions, std::span<const uint32_t> from,
                     const TriangleGrid& to, float spacing, float cap,
                     std::chrono::steady_clock::time_point deadline) {
  const size_t triangles = from.size() / 3;
  // Triangle t's pieces (ForEachPiece) are sampled on grids whose
  // sub-triangles have edges <= spacing; the distance to `to` being
  // 1-Lipschitz, a piece's largest sample distance plus its covering
  // radius bounds the distance of all its points.
  const auto pieces = [&](size_t t, auto&& fn) {
    ForEachPiece(positions[from[3 * t]], positions[from[3 * t + 1]], positions[from[3 * t + 2]],
                 spacing, 0, fn);
  };
  // A few big triangles (a node's copy) are as much work as many small
  // ones: hand them out one by one.
  const size_t chunk = std::clamp<size_t>(triangles / (8 * WorkerCount()), 1, 256);
  // The bound is at least every piece's covering radius: start there.
  std::atomic<uint32_t> worst{0};
  ParallelFor(triangles, std::max<size_t>(chunk, 64), [&](size_t t) {
    pieces(t, [&](const glm::vec3&, const glm::vec3&, const glm::vec3&, int, float covering) {
      AtomicMax(worst, covering);
    });
  });
  std::atomic<bool> capped{false};
  ParallelFor(triangles, chunk, [&](size_t t) {
    if (capped.load(std::memory_order_relaxed)) return;
    if (t % 64 == 0 && deadline != std::chrono::steady_clock::time_point::max() &&
        std::chrono::steady_clock::now() >= deadline) {
      capped.store(true, std::memory_order_relaxed);
      return;
    }
    float largest = 0.0f;
    pieces(t, [&](const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, int k,
                  float covering) {
      if (largest >= cap) return;
      // A sample within `recorded` of `to` raises neither this piece's
      // largest sample so far nor, with the covering radius, the bound
      // already recorded, so its query may stop at the first triangle that
      // close (an upper bound of its distance, itself within `recorded`):
      // the result is the bound the exact distances give, found faster.
      const float recorded = FloatOf(worst.load(std::memory_order_relaxed)) - covering;
      float local = 0.0f;
      for (int i = 0; i <= k && local < cap; ++i) {
        for (int j = 0; i + j <= k; ++j) {
          const glm::vec3 p = a + (b - a) * (float(i) / float(k)) + (c - a) * (float(j) / float(k));
          local = std::max(local, to.Distance(p, cap, std::max(local, recorded)));
          if (local >= cap) break;
        }
      }
      largest = std::max(largest, local + covering);
      AtomicMax(worst, std::min(largest, cap));
    });
    if (largest >= cap) capped.store(true, std::memory_order_relaxed);
  });
  return capped.load() ? cap : FloatOf(worst.load());
}

}  // namespace gistream
