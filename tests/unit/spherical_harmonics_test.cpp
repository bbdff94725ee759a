// The SH machinery of `sh_probes` against closed forms: projections of a
// constant and of a clamped-cosine lobe (Nijasure et al. 2005, Eq. 2 and 6),
// irradiance of a constant field, rotation of a lobe.
#include <cmath>

#include <gtest/gtest.h>

#include "solvers/sh_probes/spherical_harmonics.h"

namespace gistream::sh {
namespace spherical_harmonics_test {

constexpr double kPi = 3.14159265358979323846;

TEST(SphericalHarmonics, TexelSolidAnglesCoverTheSphere) {
  double sum = 0.0;
  for (int j = 0; j < 7; ++j) {
    for (int i = 0; i < 7; ++i) sum += TexelSolidAngle(i, j, 7);
  }
  EXPECT_NEAR(6.0 * sum, 4.0 * kPi, 1e-12);
}

TEST(SphericalHarmonics, FacesAreOrthonormalAndCoverEveryAxis) {
  for (int f = 0; f < 6; ++f) {
    EXPECT_NEAR(glm::dot(Forward(f), Up(f)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(Right(f)), 1.0, 1e-12);
    // The centre texel of an odd face looks straight along the face axis.
    EXPECT_NEAR(glm::dot(TexelDirection(f, 2, 2, 5), Forward(f)), 1.0, 1e-12);
  }
}

TEST(SphericalHarmonics, ConstantProjectsToTheDcTermOnly) {
  const Coefficients c = ProjectCube([](const glm::dvec3&) { return glm::dvec3(2.0); }, 32, 3);
  // L_00 = L * 4 pi * Y_00 = L * sqrt(4 pi).
  EXPECT_NEAR(c[0].x, 2.0 * std::sqrt(4.0 * kPi), 1e-3);
  for (int k = 1; k < kMaxCoefficients; ++k) EXPECT_NEAR(c[size_t(k)].x, 0.0, 1e-3) << k;
}

TEST(SphericalHarmonics, IrradianceOfConstantRadianceIsPiL) {
  const Coefficients c = ProjectCube([](const glm::dvec3&) { return glm::dvec3(0.7); }, 32, 3);
  for (const glm::dvec3 n : {glm::dvec3(0, 1, 0), glm::normalize(glm::dvec3(1, -2, 0.5))}) {
    EXPECT_NEAR(Irradiance(c, n, 3).x, kPi * 0.7, 1e-3);
    EXPECT_NEAR(Irradiance(c, n, 1).x, kPi * 0.7, 1e-3);  // the DC term alone
  }
}

// max(0, dot(dir, axis)): Eq. 6's lobe with k_d = pi.
Coefficients CosineLobe(const glm::dvec3& axis, int face_size) {
  return ProjectCube(
      [&](const glm::dvec3& d) { return glm::dvec3(std::max(0.0, glm::dot(d, axis))); }, face_size,
      3);
}

TEST(SphericalHarmonics, ClampedCosineLobeGivesEquationSix) {
  const Coefficients c = CosineLobe({0, 0, 1}, 64);
  EXPECT_NEAR(c[0].x, std::sqrt(kPi) / 2.0, 1e-3);        // l = 0
  EXPECT_NEAR(c[2].x, std::sqrt(kPi / 3.0), 1e-3);        // l = 1, m = 0
  EXPECT_NEAR(c[6].x, std::sqrt(5.0 * kPi) / 8.0, 1e-3);  // l = 2, m = 0
  for (int k : {1, 3, 4, 5, 7, 8}) EXPECT_NEAR(c[size_t(k)].x, 0.0, 1e-3) << k;
}

TEST(SphericalHarmonics, RotatingTheLobeRotatesTheCoefficients) {
  // A zonal lobe about axis a has L_lm = sqrt(4 pi / (2l + 1)) rho_l Y_lm(a)
  // (the rotation formula behind Eq. 4).
  const double rho[3] = {std::sqrt(kPi) / 2.0, std::sqrt(kPi / 3.0), std::sqrt(5.0 * kPi) / 8.0};
  for (const glm::dvec3 axis : {glm::normalize(glm::dvec3(1, 2, 3)),
                                glm::normalize(glm::dvec3(-0.3, 0.1, -1)), glm::dvec3(1, 0, 0)}) {
    const Coefficients c = CosineLobe(axis, 64);
    const auto y = Basis(axis);
    for (int k = 0; k < kMaxCoefficients; ++k) {
      const int l = BandOf(k);
      const double expected = std::sqrt(4.0 * kPi / (2 * l + 1)) * rho[l] * y[size_t(k)];
      EXPECT_NEAR(c[size_t(k)].x, expected, 1e-3) << "k " << k;
    }
  }
}

TEST(SphericalHarmonics, LambertConvolutionOfALobe) {
  // Irradiance at n from radiance cos(theta) about +Z, clamped: for n = +Z
  // it is the integral of cos^2 over the hemisphere, 2 pi / 3; the 9-term
  // approximation is within Ramamoorthi and Hanrahan's ~1 %.
  const Coefficients c = CosineLobe({0, 0, 1}, 64);
  EXPECT_NEAR(Irradiance(c, {0, 0, 1}, 3).x, 2.0 * kPi / 3.0, 0.01 * 2.0 * kPi / 3.0);
}

}  // namespace spherical_harmonics_test
}  // namespace gistream::sh
