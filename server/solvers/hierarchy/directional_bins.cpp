#include "solvers/hierarchy/directional_bins.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "util/constants.h"

namespace gistream::hierarchy {
namespace {

// Cube-map face and texel of a direction.
void CubeCoords(const glm::vec3& d, int res, int* face, int* x, int* y) {
  const glm::vec3 a = glm::abs(d);
  float u, v, m;
  if (a.x >= a.y && a.x >= a.z) {
    *face = d.x > 0 ? 0 : 1, m = a.x, u = d.y, v = d.z;
  } else if (a.y >= a.z) {
    *face = d.y > 0 ? 2 : 3, m = a.y, u = d.x, v = d.z;
  } else {
    *face = d.z > 0 ? 4 : 5, m = a.z, u = d.x, v = d.y;
  }
  const float s = 0.5f * (u / m + 1.0f), t = 0.5f * (v / m + 1.0f);
  *x = std::clamp(int(s * float(res)), 0, res - 1);
  *y = std::clamp(int(t * float(res)), 0, res - 1);
}

glm::vec3 CubeDirection(int face, int x, int y, int res) {
  const float u = 2.0f * (float(x) + 0.5f) / float(res) - 1.0f;
  const float v = 2.0f * (float(y) + 0.5f) / float(res) - 1.0f;
  glm::vec3 d;
  switch (face) {
    case 0: d = {1, u, v}; break;
    case 1: d = {-1, u, v}; break;
    case 2: d = {u, 1, v}; break;
    case 3: d = {u, -1, v}; break;
    case 4: d = {u, v, 1}; break;
    default: d = {u, v, -1}; break;
  }
  return glm::normalize(d);
}

}  // namespace

float DirectionalBins::ResolvedRoughness() const { return std::sqrt(0.5f * spacing_); }

absl::StatusOr<DirectionalBins> DirectionalBins::Create(int m) {
  if (m < 8 || m > 4096 || m % 2 != 0) {
    return absl::InvalidArgumentError(absl::StrCat("params.bins: ", m, " must be even, 8..4096"));
  }
  DirectionalBins b;
  b.direction_.resize(size_t(m));
  // Upper half of a spherical Fibonacci set of m points, mirrored.
  const float golden = (1.0f + std::sqrt(5.0f)) * 0.5f;
  for (int i = 0; i < m / 2; ++i) {
    const float z = 1.0f - (2.0f * float(i) + 1.0f) / float(m);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * float(i) / golden;
    const glm::vec3 d(r * std::cos(phi), r * std::sin(phi), z);
    b.direction_[size_t(i)] = d;
    b.direction_[size_t(m - 1 - i)] = -d;
  }
  b.omega_bin_ = 4.0f * kPi / float(m);
  b.spacing_ = std::sqrt(b.omega_bin_);

  // Nearest-bin lookup: ~16 texels per bin.
  b.lut_res_ = std::max(8, int(std::ceil(std::sqrt(16.0f * float(m) / 6.0f))));
  const int res = b.lut_res_;
  b.lut_.resize(size_t(6 * res * res));
  for (int f = 0; f < 6; ++f) {
    for (int y = 0; y < res; ++y) {
      for (int x = 0; x < res; ++x) {
        const glm::vec3 d = CubeDirection(f, x, y, res);
        int best = 0;
        float best_dot = -2.0f;
        for (int j = 0; j < m; ++j) {
          const float c = glm::dot(d, b.direction_[size_t(j)]);
          if (c > best_dot) best_dot = c, best = j;
        }
        b.lut_[size_t((f * res + y) * res + x)] = uint16_t(best);
      }
    }
  }

  // Cone levels: 0 = one bin, then half-angles growing by sqrt(2) from the
  // bin's own radius to a hemisphere.
  const float bin_radius = std::sqrt(b.omega_bin_ / kPi);
  b.cone_angle_.push_back(bin_radius);
  for (float a = bin_radius * std::sqrt(2.0f); b.cone_angle_.back() < 0.5f * kPi;
       a *= std::sqrt(2.0f)) {
    b.cone_angle_.push_back(std::min(a, 0.5f * kPi));
  }
  const int levels = int(b.cone_angle_.size());
  b.row_.reserve(size_t(levels * m + 1));
  b.row_.push_back(0);
  const float two_sigma2 = 2.0f * b.spacing_ * b.spacing_;
  for (int l = 0; l < levels; ++l) {
    const float support = b.cone_angle_[size_t(l)] + 0.5f * b.spacing_;
    for (int j = 0; j < m; ++j) {
      const size_t begin = b.taps_.size();
      if (l == 0) {
        b.taps_.push_back({uint16_t(j), 1.0f});
      } else {
        double sum = 0.0;
        for (int k = 0; k < m; ++k) {
          const float a = std::acos(
              std::clamp(glm::dot(b.direction_[size_t(j)], b.direction_[size_t(k)]), -1.0f, 1.0f));
          if (a > support) continue;
          const float w = std::exp(-a * a / two_sigma2);
          b.taps_.push_back({uint16_t(k), w});
          sum += w;
        }
        for (size_t t = begin; t < b.taps_.size(); ++t)
          b.taps_[t].weight = float(b.taps_[t].weight / sum);
      }
      b.row_.push_back(uint32_t(b.taps_.size()));
    }
  }
  return b;
}

int DirectionalBins::Find(const glm::vec3& d) const {
  int f, x, y;
  CubeCoords(d, lut_res_, &f, &x, &y);
  return lut_[size_t((f * lut_res_ + y) * lut_res_ + x)];
}

int DirectionalBins::ConeLevel(float theta) const {
  for (int l = 0; l < cone_levels(); ++l) {
    if (theta <= cone_angle_[size_t(l)]) return l;
  }
  return cone_levels() - 1;
}

std::pair<const DirectionalBins::Tap*, const DirectionalBins::Tap*> DirectionalBins::Row(
    int level, int j) const {
  const size_t r = size_t(level) * direction_.size() + size_t(j);
  return {taps_.data() + row_[r], taps_.data() + row_[r + 1]};
}

}  // namespace gistream::hierarchy
