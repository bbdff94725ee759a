#include "solvers/avg/tri_box_overlap.h"

#include <algorithm>
#include <cmath>

namespace gistream::avg {
namespace {

// Projects the triangle (v0, v1, v2) and the box (half extents h) onto
// `axis`; true when the projections are disjoint (a separating axis).
bool Separated(const glm::vec3& axis, const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2,
               const glm::vec3& h) {
  const float p0 = glm::dot(axis, v0), p1 = glm::dot(axis, v1), p2 = glm::dot(axis, v2);
  const float r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
  const float lo = std::min({p0, p1, p2}), hi = std::max({p0, p1, p2});
  return lo > r || hi < -r;
}

}  // namespace

bool TriangleBoxOverlap(const glm::vec3& center, const glm::vec3& half, const glm::vec3& a,
                        const glm::vec3& b, const glm::vec3& c) {
  // Box-centred coordinates.
  const glm::vec3 v0 = a - center, v1 = b - center, v2 = c - center;
  // 1. The box's face normals (the triangle's bounding box against the box).
  for (int i = 0; i < 3; ++i) {
    const float lo = std::min({v0[i], v1[i], v2[i]}), hi = std::max({v0[i], v1[i], v2[i]});
    if (lo > half[i] || hi < -half[i]) return false;
  }
  // 2. The triangle's plane.
  const glm::vec3 e0 = v1 - v0, e1 = v2 - v1, e2 = v0 - v2;
  const glm::vec3 n = glm::cross(e0, e1);
  if (Separated(n, v0, v1, v2, half)) return false;
  // 3. The nine cross products of box axes and triangle edges. A zero axis
  // (edge parallel to a box axis) separates nothing and is skipped by the
  // test itself (projections all 0 <= r).
  const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const glm::vec3& u : axes) {
    for (const glm::vec3& e : {e0, e1, e2}) {
      if (Separated(glm::cross(u, e), v0, v1, v2, half)) return false;
    }
  }
  return true;
}

}  // namespace gistream::avg
