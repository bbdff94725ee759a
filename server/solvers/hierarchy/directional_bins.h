// Directional discretization of Dachsbacher et al. 2007, Section 3.1 (shared
// with implicit_visibility's glossy elements, which store their outgoing
// radiance per bin as Dong et al. 2007, Section 4.3, describe): m
// bins Omega_j with main directions omega_j, each of solid angle
// omega_bin = 4 pi / m, plus the precomputed spreading/filter tables of
// Section 4.2 (one m-row table per cone size sigma).
//
// The directions are a spherical Fibonacci set (near-uniform, so the
// Gaussian spreading with standard deviation sqrt(4 pi / m) is meaningful),
// made antipodal: bin m-1-j is -omega_j, so the antiradiance of Eq. 19
// (light from omega_j leaving towards -omega_j) lands exactly in a bin.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "absl/status/statusor.h"

namespace gistream::hierarchy {

class DirectionalBins {
 public:
  // m even, 8..4096.
  static absl::StatusOr<DirectionalBins> Create(int m);

  int count() const { return int(direction_.size()); }
  const glm::vec3& direction(int j) const { return direction_[size_t(j)]; }
  int opposite(int j) const { return count() - 1 - j; }
  float omega_bin() const { return omega_bin_; }
  // Angle between a bin and its nearest neighbour, sqrt(4 pi / m): the
  // Gaussian's standard deviation (Section 3.1).
  float spacing() const { return spacing_; }
  // The sharpest GGX roughness the bins resolve: alpha = roughness^2 no
  // smaller than half the spacing, so a reflected lobe (about 1.3 alpha
  // wide at half maximum) spans more than a bin; a sharper material is
  // blurred to it (antiradiance's glossy leaves, implicit_visibility's
  // glossy elements).
  float ResolvedRoughness() const;
  // The bin whose main direction is nearest to unit d (a cube-map lookup
  // table, nearest bin per texel centre).
  int Find(const glm::vec3& d) const;
  // Find's table, for a GPU twin (implicit_visibility/glossy.glsl): the
  // bin of texel (face, y, x) of a lut_res() x lut_res() cube map at
  // lut()[(face * lut_res() + y) * lut_res() + x].
  int lut_res() const { return lut_res_; }
  const std::vector<uint16_t>& lut() const { return lut_; }

  // Spreading (Section 3.1, "spread and filter its energy to the bin's
  // neighbours"): cone level 0 is a single bin; level l > 0 covers a cone
  // of half-angle ConeAngle(l), weights exp(-a^2 / (2 spacing^2)) over the
  // bins within it, normalized to sum 1 (no energy created or lost).
  int cone_levels() const { return int(cone_angle_.size()); }
  float ConeAngle(int level) const { return cone_angle_[size_t(level)]; }
  // The smallest level whose cone holds a sender of half-angle `theta`.
  int ConeLevel(float theta) const;
  struct Tap {
    uint16_t bin;
    float weight;
  };
  // Taps of bin j at cone level l: [row_begin, row_end) of taps().
  std::pair<const Tap*, const Tap*> Row(int level, int j) const;
  uint64_t table_bytes() const {
    return taps_.size() * sizeof(Tap) + row_.size() * sizeof(uint32_t);
  }

 private:
  std::vector<glm::vec3> direction_;
  float omega_bin_ = 0.0f;
  float spacing_ = 0.0f;
  int lut_res_ = 0;
  std::vector<uint16_t> lut_;  // 6 faces x lut_res^2
  std::vector<float> cone_angle_;
  std::vector<uint32_t> row_;  // levels x m + 1 offsets into taps_
  std::vector<Tap> taps_;
};

}  // namespace gistream::hierarchy
