#include "solvers/shading/env_light.h"

#include <algorithm>
#include <cmath>

#include "solvers/shading/sampling.h"
#include "util/constants.h"

namespace gistream::shading {
namespace {

// Index i with cdf[i] <= t < cdf[i + 1] among n bins (cdf has n + 1
// entries), and t's fraction inside that bin.
int FindBin(const double* cdf, int n, double t, float& fraction) {
  const int i = std::clamp(int(std::upper_bound(cdf, cdf + n + 1, t) - cdf) - 1, 0, n - 1);
  const double width = cdf[i + 1] - cdf[i];
  fraction = width > 0.0 ? float(std::clamp((t - cdf[i]) / width, 0.0, 1.0 - 1e-7)) : 0.5f;
  return i;
}

}  // namespace

EnvironmentLight::EnvironmentLight(const Image& image) : image_(image) {
  const size_t texels = size_t(std::max(image.width, 0)) * size_t(std::max(image.height, 0));
  if (texels == 0 || image.pixelsf.size() < texels * 4) return;
  width_ = image.width;
  height_ = image.height;
  weight_.resize(texels);
  row_cdf_.assign(size_t(height_) + 1, 0.0);
  cell_cdf_.assign(size_t(height_) * size_t(width_ + 1), 0.0);
  for (int y = 0; y < height_; ++y) {
    // sin(theta) at the row centre: texels near the poles cover less solid angle.
    const float sin_theta = std::sin((float(y) + 0.5f) / float(height_) * kPi);
    double* row = &cell_cdf_[size_t(y) * size_t(width_ + 1)];
    for (int x = 0; x < width_; ++x) {
      const float* p = &image.pixelsf[(size_t(y) * size_t(width_) + size_t(x)) * 4];
      float w = Luminance(glm::max(glm::vec3(p[0], p[1], p[2]), glm::vec3(0.0f))) * sin_theta;
      if (!std::isfinite(w)) w = 0.0f;  // never sampled; Radiance still reports it
      weight_[size_t(y) * size_t(width_) + size_t(x)] = w;
      row[x + 1] = row[x] + double(w);
    }
    row_cdf_[size_t(y) + 1] = row_cdf_[size_t(y)] + row[width_];
  }
  total_ = row_cdf_[size_t(height_)];
}

void EnvironmentLight::Locate(const glm::vec3& dir, float rotation, int& x, int& y,
                              float& sin_theta) const {
  const float phi = std::atan2(dir.x, -dir.z) - rotation;
  const float theta = std::acos(std::clamp(dir.y, -1.0f, 1.0f));
  float u = phi / (2.0f * kPi);
  u -= std::floor(u);
  x = std::clamp(int(u * float(width_)), 0, width_ - 1);
  y = std::clamp(int(theta / kPi * float(height_)), 0, height_ - 1);
  sin_theta = std::sin(theta);
}

glm::vec3 EnvironmentLight::Radiance(const glm::vec3& dir, float rotation) const {
  if (width_ <= 0) return glm::vec3(0.0f);
  int x = 0, y = 0;
  float sin_theta = 0.0f;
  Locate(dir, rotation, x, y, sin_theta);
  const float* p = &image_.pixelsf[(size_t(y) * size_t(width_) + size_t(x)) * 4];
  return glm::vec3(p[0], p[1], p[2]);
}

float EnvironmentLight::Pdf(const glm::vec3& dir, float rotation) const {
  if (empty()) return 0.0f;
  int x = 0, y = 0;
  float sin_theta = 0.0f;
  Locate(dir, rotation, x, y, sin_theta);
  if (!(sin_theta > 0.0f)) return 0.0f;
  // pdf over (u, v) in [0,1)^2 is w / total * W * H; d(omega) = 2 pi^2 sin(theta) du dv.
  const double pdf_uv = double(weight_[size_t(y) * size_t(width_) + size_t(x)]) / total_ *
                        double(width_) * double(height_);
  return float(pdf_uv / (2.0 * double(kPi) * double(kPi) * double(sin_theta)));
}

glm::vec3 EnvironmentLight::Sample(float u1, float u2, float rotation, float& pdf) const {
  pdf = 0.0f;
  if (empty()) return glm::vec3(0.0f, 1.0f, 0.0f);
  float fy = 0.0f, fx = 0.0f;
  const int y = FindBin(row_cdf_.data(), height_, double(u1) * total_, fy);
  const double* row = &cell_cdf_[size_t(y) * size_t(width_ + 1)];
  const int x = FindBin(row, width_, double(u2) * row[width_], fx);
  const float w = weight_[size_t(y) * size_t(width_) + size_t(x)];
  if (!(w > 0.0f)) return glm::vec3(0.0f, 1.0f, 0.0f);
  const float theta = (float(y) + fy) / float(height_) * kPi;
  const float phi = (float(x) + fx) / float(width_) * 2.0f * kPi + rotation;
  const float sin_theta = std::sin(theta);
  if (!(sin_theta > 0.0f)) return glm::vec3(0.0f, 1.0f, 0.0f);
  // Inverse of Locate: phi = atan2(x, -z) - rotation.
  const glm::vec3 dir(sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi));
  const double pdf_uv = double(w) / total_ * double(width_) * double(height_);
  pdf = float(pdf_uv / (2.0 * double(kPi) * double(kPi) * double(sin_theta)));
  return dir;
}

}  // namespace gistream::shading
