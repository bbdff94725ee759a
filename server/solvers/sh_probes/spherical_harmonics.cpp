#include "solvers/sh_probes/spherical_harmonics.h"

#include <cmath>
#include <numbers>

namespace gistream::sh {
namespace {

// Face table: +X, -X, +Y, -Y, +Z, -Z, each with an up vector orthogonal to it.
constexpr double kForward[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                   {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
constexpr double kUp[6][3] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};

// The integral of the cube face's solid-angle density from (0,0) to (x, y).
double AreaElement(double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0)); }

}  // namespace

std::array<double, kMaxCoefficients> Basis(const glm::dvec3& d) {
  // Appendix Eq. 7 in real form (Ramamoorthi and Hanrahan 2001's constants).
  return {0.282094791773878,
          0.488602511902920 * d.y,
          0.488602511902920 * d.z,
          0.488602511902920 * d.x,
          1.092548430592079 * d.x * d.y,
          1.092548430592079 * d.y * d.z,
          0.315391565252520 * (3.0 * d.z * d.z - 1.0),
          1.092548430592079 * d.x * d.z,
          0.546274215296040 * (d.x * d.x - d.y * d.y)};
}

glm::dvec3 Forward(int face) { return {kForward[face][0], kForward[face][1], kForward[face][2]}; }
glm::dvec3 Up(int face) { return {kUp[face][0], kUp[face][1], kUp[face][2]}; }
glm::dvec3 Right(int face) { return glm::cross(Forward(face), Up(face)); }

glm::dvec3 TexelDirection(int face, int i, int j, int size) {
  const double u = 2.0 * (i + 0.5) / size - 1.0;
  const double v = 2.0 * (j + 0.5) / size - 1.0;
  return glm::normalize(Forward(face) + u * Right(face) + v * Up(face));
}

double TexelSolidAngle(int i, int j, int size) {
  const double x0 = 2.0 * i / size - 1.0, x1 = 2.0 * (i + 1) / size - 1.0;
  const double y0 = 2.0 * j / size - 1.0, y1 = 2.0 * (j + 1) / size - 1.0;
  return AreaElement(x0, y0) - AreaElement(x0, y1) - AreaElement(x1, y0) + AreaElement(x1, y1);
}

Coefficients ProjectCube(const std::function<glm::dvec3(const glm::dvec3&)>& radiance,
                         int face_size, int bands) {
  Coefficients c{};
  const int count = CoefficientCount(bands);
  for (int face = 0; face < 6; ++face) {
    for (int j = 0; j < face_size; ++j) {
      for (int i = 0; i < face_size; ++i) {
        const glm::dvec3 dir = TexelDirection(face, i, j, face_size);
        const glm::dvec3 l = radiance(dir) * TexelSolidAngle(i, j, face_size);
        const auto y = Basis(dir);
        for (int k = 0; k < count; ++k) c[size_t(k)] += l * y[size_t(k)];
      }
    }
  }
  return c;
}

double LambertFactor(int band) {
  switch (band) {
    case 0: return std::numbers::pi;
    case 1: return 2.0 * std::numbers::pi / 3.0;
    case 2: return std::numbers::pi / 4.0;
    default: return 0.0;  // odd bands above 1 vanish (Eq. 6); l > 2 is not stored
  }
}

glm::dvec3 Irradiance(const Coefficients& c, const glm::dvec3& normal, int bands) {
  const auto y = Basis(normal);
  glm::dvec3 e(0.0);
  for (int k = 0; k < CoefficientCount(bands); ++k) {
    e += LambertFactor(BandOf(k)) * c[size_t(k)] * y[size_t(k)];
  }
  return e;
}

}  // namespace gistream::sh
