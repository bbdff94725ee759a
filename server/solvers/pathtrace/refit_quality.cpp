#include "solvers/pathtrace/refit_quality.h"

#include <algorithm>
#include <numeric>

namespace gistream::pathtrace {
namespace {

constexpr size_t kArity = 4;  // children per node and triangles per leaf, as Embree's BVH4

// 10 bits per axis interleaved (a 30-bit Morton code).
uint32_t Spread(uint32_t x) {
  x &= 0x3ffu;
  x = (x | (x << 16)) & 0x030000ffu;
  x = (x | (x << 8)) & 0x0300f00fu;
  x = (x | (x << 4)) & 0x030c30c3u;
  x = (x | (x << 2)) & 0x09249249u;
  return x;
}

double Area(const Bounds& b) {
  if (b.empty()) return 0.0;
  const glm::dvec3 e = glm::dvec3(b.extent());
  return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

}  // namespace

RefitQuality::RefitQuality(const std::vector<Bounds>& boxes) {
  Bounds centroids;
  for (const Bounds& b : boxes) centroids.Extend(b.center());
  const glm::vec3 extent = glm::max(centroids.extent(), glm::vec3(1e-30f));
  std::vector<uint32_t> code(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) {
    const glm::vec3 u = glm::clamp((boxes[i].center() - centroids.min) / extent, 0.0f, 1.0f);
    code[i] = (Spread(uint32_t(u.x * 1023.0f)) << 2) | (Spread(uint32_t(u.y * 1023.0f)) << 1) |
              Spread(uint32_t(u.z * 1023.0f));
  }
  order_.resize(boxes.size());
  std::iota(order_.begin(), order_.end(), 0u);
  std::stable_sort(order_.begin(), order_.end(),
                   [&](uint32_t a, uint32_t b) { return code[a] < code[b]; });
  built_cost_ = Cost(boxes);
}

double RefitQuality::Cost(const std::vector<Bounds>& boxes) const {
  // Level by level from the leaves: each node's box is the union of its
  // (up to) kArity children, the leaves' the union of kArity triangles.
  std::vector<Bounds> level;
  for (size_t i = 0; i < order_.size(); i += kArity) {
    Bounds leaf;
    for (size_t j = i; j < std::min(i + kArity, order_.size()); ++j) leaf.Extend(boxes[order_[j]]);
    level.push_back(leaf);
  }
  double sum = 0.0;
  while (true) {
    for (const Bounds& b : level) sum += Area(b);
    if (level.size() <= 1) break;
    std::vector<Bounds> parents;
    for (size_t i = 0; i < level.size(); i += kArity) {
      Bounds parent;
      for (size_t j = i; j < std::min(i + kArity, level.size()); ++j) parent.Extend(level[j]);
      parents.push_back(parent);
    }
    level = std::move(parents);
  }
  const double root = level.empty() ? 0.0 : Area(level.front());
  return root > 0.0 ? sum / root : 0.0;
}

double RefitQuality::Growth(const std::vector<Bounds>& boxes) const {
  if (order_.empty() || !(built_cost_ > 0.0)) return 1.0;
  return Cost(boxes) / built_cost_;
}

}  // namespace gistream::pathtrace
