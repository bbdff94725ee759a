#include "encode/video/yuv.h"

#include <algorithm>
#include <cmath>

namespace gistream {
namespace {

// BT.709 luma weights.
constexpr float kKr = 0.2126f, kKg = 0.7152f, kKb = 0.0722f;

uint8_t Clamp8(float v) { return uint8_t(std::clamp(std::lround(v), 0L, 255L)); }

}  // namespace

void RgbaToYuv420(std::span<const uint8_t> rgba, const Yuv420Planes& out) {
  const int w = out.width, h = out.height;
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = rgba.data() + size_t(y) * size_t(w) * 4;
    uint8_t* yrow = out.y + size_t(y) * size_t(out.y_stride);
    for (int x = 0; x < w; ++x) {
      const float r = row[4 * x], g = row[4 * x + 1], b = row[4 * x + 2];
      yrow[x] = Clamp8(16.0f + 219.0f / 255.0f * (kKr * r + kKg * g + kKb * b));
    }
  }
  for (int cy = 0; cy < h / 2; ++cy) {
    const uint8_t* r0 = rgba.data() + size_t(2 * cy) * size_t(w) * 4;
    const uint8_t* r1 = r0 + size_t(w) * 4;
    uint8_t* urow = out.u + size_t(cy) * size_t(out.c_stride);
    uint8_t* vrow = out.v + size_t(cy) * size_t(out.c_stride);
    for (int cx = 0; cx < w / 2; ++cx) {
      const int i = 8 * cx;
      const float r = 0.25f * float(r0[i] + r0[i + 4] + r1[i] + r1[i + 4]);
      const float g = 0.25f * float(r0[i + 1] + r0[i + 5] + r1[i + 1] + r1[i + 5]);
      const float b = 0.25f * float(r0[i + 2] + r0[i + 6] + r1[i + 2] + r1[i + 6]);
      const float luma = kKr * r + kKg * g + kKb * b;
      urow[cx] = Clamp8(128.0f + 224.0f / 255.0f * (b - luma) / (2.0f * (1.0f - kKb)));
      vrow[cx] = Clamp8(128.0f + 224.0f / 255.0f * (r - luma) / (2.0f * (1.0f - kKr)));
    }
  }
}

std::vector<uint8_t> Yuv420ToRgba(const uint8_t* y, int y_stride, const uint8_t* u,
                                  const uint8_t* v, int c_stride, int width, int height) {
  std::vector<uint8_t> rgba(size_t(width) * size_t(height) * 4);
  for (int py = 0; py < height; ++py) {
    for (int px = 0; px < width; ++px) {
      const float luma =
          (float(y[size_t(py) * size_t(y_stride) + size_t(px)]) - 16.0f) * 255.0f / 219.0f;
      const size_t c = size_t(py / 2) * size_t(c_stride) + size_t(px / 2);
      const float cb = (float(u[c]) - 128.0f) * 255.0f / 224.0f;
      const float cr = (float(v[c]) - 128.0f) * 255.0f / 224.0f;
      const float r = luma + 2.0f * (1.0f - kKr) * cr;
      const float b = luma + 2.0f * (1.0f - kKb) * cb;
      const float g = (luma - kKr * r - kKb * b) / kKg;
      uint8_t* o = rgba.data() + (size_t(py) * size_t(width) + size_t(px)) * 4;
      o[0] = Clamp8(r);
      o[1] = Clamp8(g);
      o[2] = Clamp8(b);
      o[3] = 255;
    }
  }
  return rgba;
}

}  // namespace gistream
