// Encoders round-trip through our decoders: PNG exactly, JPEG within a
// stated error, EXR float-exact (including tiny and huge radiances).
#include <cmath>

#include <gtest/gtest.h>

#include "encode/encode.h"

namespace gistream {
namespace {

std::span<const uint8_t> AsBytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

std::vector<uint8_t> Gradient(int w, int h) {
  std::vector<uint8_t> rgba(size_t(w * h * 4));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t* p = &rgba[size_t((y * w + x) * 4)];
      p[0] = uint8_t(x * 255 / (w - 1));
      p[1] = uint8_t(y * 255 / (h - 1));
      p[2] = uint8_t(128);
      p[3] = 255;
    }
  }
  return rgba;
}

TEST(Encode, PngRoundTripIsExact) {
  const int w = 37, h = 21;  // odd sizes catch row-stride bugs
  const std::vector<uint8_t> rgba = Gradient(w, h);
  auto png = EncodePng(rgba, w, h);
  ASSERT_TRUE(png.ok()) << png.status();
  auto decoded = DecodeImageBytes(AsBytes(*png));
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  ASSERT_EQ(decoded->width, w);
  ASSERT_EQ(decoded->height, h);
  for (size_t i = 0; i < rgba.size(); ++i) {
    ASSERT_NEAR(decoded->rgba[i] * 255.0f, float(rgba[i]), 1e-3f) << "at " << i;
  }
}

TEST(Encode, JpegRoundTripIsClose) {
  const int w = 64, h = 48;
  const std::vector<uint8_t> rgba = Gradient(w, h);
  auto jpeg = EncodeJpeg(rgba, w, h, 95);
  ASSERT_TRUE(jpeg.ok()) << jpeg.status();
  EXPECT_EQ(uint8_t((*jpeg)[0]), 0xFF);
  EXPECT_EQ(uint8_t((*jpeg)[1]), 0xD8);
  auto decoded = DecodeImageBytes(AsBytes(*jpeg));
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  ASSERT_EQ(decoded->width, w);
  double error = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    error += std::abs(double(decoded->rgba[i]) * 255.0 - double(rgba[i]));
    ++n;
  }
  // Quality 95 on a smooth gradient: mean error under 3 levels of 255.
  EXPECT_LT(error / double(n), 3.0);
}

TEST(Encode, ExrKeepsFloatsExactly) {
  const int w = 5, h = 3;
  std::vector<float> rgba(size_t(w * h * 4));
  const float values[] = {0.0f, 1e-3f, 0.5f, 1.0f, 17.0f, 1e5f, 3.14159f};
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = (i % 4 == 3) ? 1.0f : values[i % 7];
  auto exr = EncodeExr(rgba, w, h);
  ASSERT_TRUE(exr.ok()) << exr.status();
  auto decoded = DecodeImageBytes(AsBytes(*exr));
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  ASSERT_EQ(decoded->width, w);
  ASSERT_EQ(decoded->height, h);
  for (size_t i = 0; i < rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    EXPECT_EQ(decoded->rgba[i], rgba[i]) << "at " << i;
  }
}

TEST(Encode, SizeMismatchIsAnError) {
  std::vector<uint8_t> rgba(10);
  EXPECT_EQ(EncodePng(rgba, 4, 4).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(EncodeJpeg(rgba, 0, 4, 90).status().code(), absl::StatusCode::kInvalidArgument);
  std::vector<float> f(3);
  EXPECT_EQ(EncodeExr(f, 2, 2).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace gistream
