// Image encoders: JPEG (libjpeg-turbo), PNG (libpng), EXR (OpenEXR via
// OpenImageIO, half or float RGB). Rows are given top row first.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "util/status.h"

namespace gistream {

// rgba: width*height*4 bytes, sRGB-encoded. quality 1..100.
absl::StatusOr<std::string> EncodeJpeg(std::span<const uint8_t> rgba, int width, int height,
                                       int quality);
absl::StatusOr<std::string> EncodePng(std::span<const uint8_t> rgba, int width, int height);
// rgba: width*height*4 linear floats; written as 32-bit float RGB.
absl::StatusOr<std::string> EncodeExr(std::span<const float> rgba, int width, int height);

// Decoders for clients and tests (EXR to linear float RGBA; PNG/JPEG to
// 8-bit RGBA). Rows top first.
struct DecodedImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;  // EXR: linear; PNG/JPEG: value/255 (still sRGB)
};
absl::StatusOr<DecodedImage> DecodeImageBytes(std::span<const uint8_t> bytes);

}  // namespace gistream
