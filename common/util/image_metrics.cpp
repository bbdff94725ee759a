#include "util/image_metrics.h"

#include <algorithm>
#include <cmath>

namespace gistream {

float ToneMappedLuminance(float r, float g, float b) {
  auto curve = [](float x) {
    x = std::max(x, 0.0f);
    const float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    const float c = std::clamp(y, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  };
  return 0.2126f * curve(r) + 0.7152f * curve(g) + 0.0722f * curve(b);
}

double Ssim(const std::vector<float>& a, const std::vector<float>& b, int width, int height) {
  constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;
  constexpr int kWindow = 8;
  double sum = 0.0;
  int windows = 0;
  for (int y0 = 0; y0 < height; y0 += kWindow) {
    for (int x0 = 0; x0 < width; x0 += kWindow) {
      const int y1 = std::min(y0 + kWindow, height), x1 = std::min(x0 + kWindow, width);
      const double n = double((y1 - y0) * (x1 - x0));
      double ma = 0, mb = 0;
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          ma += a[size_t(y * width + x)];
          mb += b[size_t(y * width + x)];
        }
      }
      ma /= n;
      mb /= n;
      double va = 0, vb = 0, cov = 0;
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          const double da = a[size_t(y * width + x)] - ma, db = b[size_t(y * width + x)] - mb;
          va += da * da;
          vb += db * db;
          cov += da * db;
        }
      }
      const double d = n > 1 ? n - 1 : 1;
      va /= d;
      vb /= d;
      cov /= d;
      sum +=
          ((2 * ma * mb + kC1) * (2 * cov + kC2)) / ((ma * ma + mb * mb + kC1) * (va + vb + kC2));
      ++windows;
    }
  }
  return windows ? sum / windows : 1.0;
}

absl::StatusOr<ImageError> CompareImages(const RgbaImage& image, const RgbaImage& reference) {
  if (image.width != reference.width || image.height != reference.height ||
      image.rgba.size() != reference.rgba.size() ||
      image.rgba.size() != size_t(image.width) * size_t(image.height) * 4) {
    return absl::InvalidArgumentError(absl::StrCat("image: ", image.width, "x", image.height,
                                                   " does not match the reference's ",
                                                   reference.width, "x", reference.height));
  }
  const size_t pixels = size_t(image.width) * size_t(image.height);
  ImageError e;
  double rel = 0.0, sq = 0.0;
  size_t finite = 0, bad = 0;
  std::vector<float> la(pixels), lb(pixels);
  for (size_t i = 0; i < pixels; ++i) {
    const float* x = &image.rgba[i * 4];
    const float* r = &reference.rgba[i * 4];
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) {
      ++bad;
      lb[i] = la[i] = ToneMappedLuminance(r[0], r[1], r[2]);
      continue;
    }
    for (int c = 0; c < 3; ++c) {
      const double d = double(x[c]) - double(r[c]);
      rel += d * d / (double(r[c]) * double(r[c]) + 0.01);
      sq += d * d;
    }
    ++finite;
    la[i] = ToneMappedLuminance(x[0], x[1], x[2]);
    lb[i] = ToneMappedLuminance(r[0], r[1], r[2]);
  }
  const double samples = double(std::max<size_t>(finite, 1) * 3);
  e.rel_mse = rel / samples;
  e.rmse = std::sqrt(sq / samples);
  e.ssim = Ssim(la, lb, image.width, image.height);
  e.nonfinite_fraction = double(bad) / double(std::max<size_t>(pixels, 1));
  return e;
}

}  // namespace gistream
