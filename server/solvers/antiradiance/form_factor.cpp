#include "solvers/antiradiance/form_factor.h"

#include <cmath>
#include <numbers>

namespace gistream::antiradiance {
namespace {

// Sutherland-Hodgman against the plane n . (p - x) = 0, keeping the front;
// a quad gains at most one corner.
int ClipFront(const CellQuad& q, const glm::dvec3& x, const glm::dvec3& n,
              std::array<glm::dvec3, 5>& out) {
  int k = 0;
  for (size_t i = 0; i < q.size(); ++i) {
    const glm::dvec3 a(q[i]), b(q[(i + 1) % q.size()]);
    const double da = glm::dot(n, a - x), db = glm::dot(n, b - x);
    if (da >= 0.0 && k < 5) out[size_t(k++)] = a;
    if ((da >= 0.0) != (db >= 0.0) && k < 5) out[size_t(k++)] = a + (b - a) * (da / (da - db));
  }
  return k;
}

}  // namespace

double PointToQuadsFormFactor(std::span<const CellQuad> quads, const glm::vec3& x,
                              const glm::vec3& n) {
  const glm::dvec3 xd(x), nd(n);
  double total = 0.0;
  for (const CellQuad& q : quads) {
    std::array<glm::dvec3, 5> poly;
    const int k = ClipFront(q, xd, nd, poly);
    if (k < 3) continue;
    // Lambert: F = 1 / (2 pi) |sum_e theta_e (n . gamma_e)|, gamma_e the unit
    // normal of the plane through x and edge e, theta_e the edge's angle at x.
    double s = 0.0;
    for (int i = 0; i < k; ++i) {
      const glm::dvec3 a = poly[size_t(i)] - xd, b = poly[size_t((i + 1) % k)] - xd;
      const glm::dvec3 c = glm::cross(a, b);
      const double len = glm::length(c);
      if (!(len > 1e-30)) continue;  // a repeated corner or an edge through x
      s += std::atan2(len, glm::dot(a, b)) * glm::dot(nd, c) / len;
    }
    total += std::abs(s) / (2.0 * std::numbers::pi);
  }
  return total;
}

}  // namespace gistream::antiradiance
