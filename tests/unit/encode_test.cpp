// Encoders round-trip through our decoders: PNG exactly, JPEG within a
// stated error, EXR float-exact (including tiny and huge radiances).
#include "encode/encode.h"

#include <gtest/gtest.h>

#include <cmath>

#include "gltf_test_util.h"

namespace gistream {
namespace encode_test {

std::span<const uint8_t> AsBytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

std::vector<uint8_t> Gradient(int w, int h) {
  std::vector<uint8_t> rgba(size_t(w) * size_t(h) * 4);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t* p = &rgba[(size_t(y) * size_t(w) + size_t(x)) * 4];
      p[0] = uint8_t(255 * x / (w - 1));
      p[1] = uint8_t(255 * y / (h - 1));
      p[2] = uint8_t(255 * (x + y) / (w + h - 2));
      p[3] = 255;
    }
  }
  return rgba;
}

TEST(Encode, PngRoundTripIsExact) {
  std::vector<uint8_t> rgba = Gradient(37, 21);
  rgba[3] = 17;  // alpha survives, unpremultiplied
  const absl::StatusOr<std::string> png = EncodePng(rgba, 37, 21);
  ASSERT_TRUE(png.ok()) << png.status();
  const absl::StatusOr<DecodedImage> back = DecodeImageBytes(AsBytes(*png));
  ASSERT_TRUE(back.ok()) << back.status();
  ASSERT_EQ(back->width, 37);
  ASSERT_EQ(back->height, 21);
  ASSERT_EQ(back->rgba.size(), rgba.size());
  for (size_t i = 0; i < rgba.size(); ++i) {
    ASSERT_EQ(std::lround(back->rgba[i] * 255.0f), rgba[i]) << i;
  }
}

TEST(Encode, JpegRoundTripIsClose) {
  const std::vector<uint8_t> rgba = Gradient(64, 48);
  const absl::StatusOr<std::string> jpeg = EncodeJpeg(rgba, 64, 48, 95);
  ASSERT_TRUE(jpeg.ok()) << jpeg.status();
  EXPECT_EQ(uint8_t((*jpeg)[0]), 0xFF);  // SOI marker
  EXPECT_EQ(uint8_t((*jpeg)[1]), 0xD8);
  const absl::StatusOr<DecodedImage> back = DecodeImageBytes(AsBytes(*jpeg));
  ASSERT_TRUE(back.ok()) << back.status();
  ASSERT_EQ(back->width, 64);
  ASSERT_EQ(back->height, 48);
  double error = 0.0;
  int n = 0;
  for (size_t i = 0; i < rgba.size(); ++i) {
    if (i % 4 == 3) {
      EXPECT_EQ(back->rgba[i], 1.0f);  // JPEG has no alpha: opaque
      continue;
    }
    error += std::abs(back->rgba[i] - rgba[i] / 255.0f);
    ++n;
  }
  // A smooth gradient at quality 95 stays within a few code values on average.
  EXPECT_LT(error / n, 3.0 / 255.0);
}

TEST(Encode, JpegQualityChangesSize) {
  const std::vector<uint8_t> rgba = Gradient(64, 64);
  EXPECT_LT(EncodeJpeg(rgba, 64, 64, 10)->size(), EncodeJpeg(rgba, 64, 64, 100)->size());
}

TEST(Encode, LargeNoisyJpegFitsItsBuffer) {
  // Noise at quality 100 is close to JPEG's worst case size.
  std::vector<uint8_t> rgba(size_t(333) * 257 * 4);
  uint32_t state = 1;
  for (uint8_t& v : rgba) v = uint8_t((state = state * 1664525u + 1013904223u) >> 24);
  const absl::StatusOr<std::string> jpeg = EncodeJpeg(rgba, 333, 257, 100);
  ASSERT_TRUE(jpeg.ok()) << jpeg.status();
  EXPECT_EQ(DecodeImageBytes(AsBytes(*jpeg))->width, 333);
}

TEST(Encode, ExrRoundTripIsExact) {
  const std::vector<float> rgba = {1e-3f, 1e5f,  0.0f,     0.25f,  // alpha is not stored
                                   3.5f,  1e-7f, 65504.0f, 1.0f,  1e20f, 0.1f, 7.0f, 0.0f};
  const absl::StatusOr<std::string> exr = EncodeExr(rgba, 3, 1);
  ASSERT_TRUE(exr.ok()) << exr.status();
  const absl::StatusOr<DecodedImage> back = DecodeImageBytes(AsBytes(*exr));
  ASSERT_TRUE(back.ok()) << back.status();
  ASSERT_EQ(back->width, 3);
  ASSERT_EQ(back->height, 1);
  for (size_t i = 0; i < rgba.size(); ++i) {
    EXPECT_EQ(back->rgba[i], i % 4 == 3 ? 1.0f : rgba[i]) << i;
  }
}

TEST(Encode, ExrRowsStayInOrder) {
  std::vector<float> rgba(2 * 3 * 4, 0.0f);
  for (int y = 0; y < 3; ++y) rgba[size_t(y) * 8] = float(y + 1);
  const absl::StatusOr<DecodedImage> back = DecodeImageBytes(AsBytes(*EncodeExr(rgba, 2, 3)));
  ASSERT_TRUE(back.ok());
  for (int y = 0; y < 3; ++y) EXPECT_EQ(back->rgba[size_t(y) * 8], float(y + 1));
}

TEST(Encode, SizesAreValidated) {
  const std::vector<uint8_t> rgba(16, 0);
  EXPECT_ERROR(EncodePng(rgba, 0, 4), kInvalidArgument, "png: size 0x4 must be positive");
  EXPECT_ERROR(EncodePng(rgba, 4, 4), kInvalidArgument, "png: got 16 values, expected 4x4x4");
  EXPECT_ERROR(EncodeJpeg(rgba, -2, 2, 90), kInvalidArgument, "jpeg: size -2x2");
  EXPECT_ERROR(EncodeJpeg(rgba, 2, 2, 0), kInvalidArgument, "jpeg.quality: 0 is out of range");
  EXPECT_ERROR(EncodeJpeg(rgba, 2, 2, 101), kInvalidArgument, "jpeg.quality: 101");
  EXPECT_ERROR(EncodeExr(std::vector<float>(3), 1, 1), kInvalidArgument,
               "exr: got 3 values, expected 1x1x4");
  EXPECT_ERROR(EncodeJpeg(rgba, 65536, 65536, 90), kInvalidArgument, "jpeg: got 16 values");
}

TEST(Encode, DecodeRefusesUnknownData) {
  const std::string junk = "not an image";
  EXPECT_ERROR(DecodeImageBytes(AsBytes(junk)), kInvalidArgument, "image: unknown format");
  const std::string png = *EncodePng(std::vector<uint8_t>(64, 1), 4, 4);
  EXPECT_ERROR(DecodeImageBytes(AsBytes(png.substr(0, 40))), kInvalidArgument,
               "image: corrupt png");
}

}  // namespace encode_test
}  // namespace gistream
