// Error of an image against a reference: what `gistream eval` reports and
// what the tests judge solvers by (one implementation for both).
// Images are linear float RGBA, rows top first, the same size.
#pragma once

#include <cstddef>
#include <vector>

#include "util/status.h"

namespace gistream {

struct RgbaImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;
};

struct ImageError {
  double rel_mse = 0.0;             // mean over pixels and RGB of (x-r)^2 / (r^2 + 0.01)
  double rmse = 0.0;                // sqrt of mean (x-r)^2 over pixels and RGB
  double ssim = 1.0;                // SSIM of tone-mapped luminance (8x8 windows)
  double nonfinite_fraction = 0.0;  // pixels with a NaN/Inf channel
};

// INVALID_ARGUMENT when the sizes differ. Non-finite pixels are counted and
// left out of the other metrics.
absl::StatusOr<ImageError> CompareImages(const RgbaImage& image, const RgbaImage& reference);

// The server's display transform (exposure 0, Narkowicz ACES fit, sRGB),
// then Rec. 709 luminance: what SSIM is computed on.
float ToneMappedLuminance(float r, float g, float b);

// Mean SSIM over non-overlapping 8x8 windows of two single-channel images
// with values in [0, 1] (C1 = (0.01)^2, C2 = (0.03)^2).
double Ssim(const std::vector<float>& a, const std::vector<float>& b, int width, int height);

}  // namespace gistream
