// Real spherical harmonics up to band l = 2 (9 coefficients), the basis of
// Nijasure et al. 2005 (Appendix, Eq. 7) in its real form, with the cube-map
// projection of Eq. 2 and the Lambertian convolution of Eq. 4 and 6. The
// GLSL twin is shaders/sh_probes/sh.glsl; the tests hold both to the same
// closed forms.
#pragma once

#include <array>
#include <functional>

#include <glm/glm.hpp>

namespace gistream::sh {

constexpr int kMaxBands = 3;
constexpr int kMaxCoefficients = kMaxBands * kMaxBands;

using Coefficients = std::array<glm::dvec3, kMaxCoefficients>;

// Number of coefficients of `bands` bands (l < bands): bands².
constexpr int CoefficientCount(int bands) { return bands * bands; }
// Band l of coefficient index k (k = l² + l + m).
constexpr int BandOf(int k) { return k < 1 ? 0 : (k < 4 ? 1 : 2); }

// Y_k(dir) for k < 9, dir unit; order (l, m) = (0,0), (1,-1), (1,0), (1,1),
// (2,-2), (2,-1), (2,0), (2,1), (2,2) with x, y, z the world axes.
std::array<double, kMaxCoefficients> Basis(const glm::dvec3& dir);

// Cube-map faces as the probes use them: face f looks along Forward(f);
// texel (i, j) of a size-s face is the direction
// Forward + u Right + v Up with u = 2 (i + 0.5) / s - 1, v likewise (j).
glm::dvec3 Forward(int face);
glm::dvec3 Up(int face);
glm::dvec3 Right(int face);  // cross(Forward, Up)
glm::dvec3 TexelDirection(int face, int i, int j, int size);

// Exact solid angle of texel (i, j) of a size-s face (the A(omega) of Eq. 2).
double TexelSolidAngle(int i, int j, int size);

// Eq. 2: L_lm = sum over the six faces' texels of L(texel) Y_lm A.
Coefficients ProjectCube(const std::function<glm::dvec3(const glm::dvec3& dir)>& radiance,
                         int face_size, int bands);

// Eq. 4 with Eq. 6's Lambertian lobe: the clamped-cosine convolution
// factors A_l = pi, 2 pi / 3, pi / 4 (Eq. 4's sqrt(4 pi / (2l + 1)) rho_l
// with k_d = pi).
double LambertFactor(int band);

// Irradiance E(n) = sum_lm A_l L_lm Y_lm(n); diffuse exitance is
// albedo / pi times this.
glm::dvec3 Irradiance(const Coefficients& c, const glm::dvec3& normal, int bands);

}  // namespace gistream::sh
