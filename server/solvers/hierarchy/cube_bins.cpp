#include "solvers/hierarchy/cube_bins.h"

#include <algorithm>
#include <cmath>

namespace gistream::hierarchy {
namespace {

// Solid angle of the face rectangle [0,x] x [0,y] at unit distance, up to
// the corner terms: Omega = F(x1,y1) - F(x0,y1) - F(x1,y0) + F(x0,y0).
double AreaElement(double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0)); }

// Face f = 2 * axis + (negative ? 1 : 0); u, v are the next two axes
// (cyclic) divided by the major component.
glm::vec3 FaceDirection(int face, double u, double v) {
  const int axis = face / 2;
  glm::dvec3 d(0.0);
  d[axis] = (face & 1) ? -1.0 : 1.0;
  d[(axis + 1) % 3] = u;
  d[(axis + 2) % 3] = v;
  return glm::vec3(glm::normalize(d));
}

}  // namespace

CubeBins::CubeBins(int n) : n_(std::max(n, 1)) {
  direction_.resize(size_t(count()));
  solid_angle_.resize(size_t(count()));
  min_solid_angle_ = 4.0f * 3.14159265f;
  const double step = 2.0 / n_;
  for (int face = 0; face < 6; ++face) {
    for (int j = 0; j < n_; ++j) {
      for (int i = 0; i < n_; ++i) {
        const double u0 = -1.0 + i * step, u1 = u0 + step;
        const double v0 = -1.0 + j * step, v1 = v0 + step;
        const int bin = (face * n_ + j) * n_ + i;
        direction_[size_t(bin)] = FaceDirection(face, 0.5 * (u0 + u1), 0.5 * (v0 + v1));
        const double omega =
            AreaElement(u1, v1) - AreaElement(u0, v1) - AreaElement(u1, v0) + AreaElement(u0, v0);
        solid_angle_[size_t(bin)] = float(omega);
        min_solid_angle_ = std::min(min_solid_angle_, float(omega));
      }
    }
  }
}

int CubeBins::Bin(const glm::vec3& dir) const {
  const glm::vec3 a = glm::abs(dir);
  int axis = 0;
  if (a.y > a.x && a.y >= a.z)
    axis = 1;
  else if (a.z > a.x && a.z > a.y)
    axis = 2;
  const float major = a[axis];
  if (!(major > 0.0f)) return 0;
  const int face = 2 * axis + (dir[axis] < 0.0f ? 1 : 0);
  const float u = dir[(axis + 1) % 3] / major, v = dir[(axis + 2) % 3] / major;
  const int i = std::clamp(int((u + 1.0f) * 0.5f * float(n_)), 0, n_ - 1);
  const int j = std::clamp(int((v + 1.0f) * 0.5f * float(n_)), 0, n_ - 1);
  return (face * n_ + j) * n_ + i;
}

float CubeBins::CosineSum(const glm::vec3& n) const {
  double sum = 0.0;
  for (int b = 0; b < count(); ++b) {
    const float c = glm::dot(n, direction_[size_t(b)]);
    if (c > 0.0f) sum += double(solid_angle_[size_t(b)]) * double(c);
  }
  return float(sum);
}

}  // namespace gistream::hierarchy
