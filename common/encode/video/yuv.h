// RGBA8 <-> planar YUV 4:2:0, BT.709 matrix, limited ("TV") range: what the
// video encoders take and the decoders give. Chroma is the box average of
// each 2x2 block. The transfer curve is untouched (the values stay sRGB-
// encoded; the encoder tags the stream as sRGB / BT.709).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace gistream {

struct Yuv420Planes {
  int width = 0;   // even
  int height = 0;  // even
  // Strides in bytes: y_stride >= width, c_stride >= width / 2.
  uint8_t* y = nullptr;
  uint8_t* u = nullptr;
  uint8_t* v = nullptr;
  int y_stride = 0;
  int c_stride = 0;
};

// rgba: width * height * 4 bytes, top row first.
void RgbaToYuv420(std::span<const uint8_t> rgba, const Yuv420Planes& out);

// The inverse, for decoders and tests; writes alpha 255.
std::vector<uint8_t> Yuv420ToRgba(const uint8_t* y, int y_stride, const uint8_t* u,
                                  const uint8_t* v, int c_stride, int width, int height);

}  // namespace gistream
