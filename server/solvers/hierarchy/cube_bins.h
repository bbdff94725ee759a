// The world-aligned cube-map discretization of the sphere of directions
// (Dong et al. 2007, Section 4.2.2 "Discretization"): 6 x N x N bins, a bin
// being one cube-map texel. Every element of the hierarchy shares the same
// table; a bin's direction, solid angle and the mapping from a direction
// are precomputed.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace gistream::hierarchy {

class CubeBins {
 public:
  // `n` bins along each face edge (the paper's N: 8, 12, 16); n >= 1.
  explicit CubeBins(int n);

  int n() const { return n_; }
  int count() const { return 6 * n_ * n_; }

  // Bin of a direction (need not be unit; the zero vector maps to bin 0).
  int Bin(const glm::vec3& dir) const;
  // Unit direction through the bin's centre.
  const glm::vec3& Direction(int bin) const { return direction_[size_t(bin)]; }
  // Exact solid angle of the bin (sum over all bins = 4 pi).
  float SolidAngle(int bin) const { return solid_angle_[size_t(bin)]; }
  // The smallest bin's solid angle (the corner bins).
  float MinSolidAngle() const { return min_solid_angle_; }
  // Sum over bins of SolidAngle * max(0, n . Direction): the discrete
  // cosine-weighted hemisphere integral (pi in the limit), used to make the
  // gather an exact quadrature of cos for every normal.
  float CosineSum(const glm::vec3& n) const;

 private:
  int n_;
  std::vector<glm::vec3> direction_;
  std::vector<float> solid_angle_;
  float min_solid_angle_ = 0.0f;
};

}  // namespace gistream::hierarchy
