// DecodeImage: magic-byte detection, one reader per format, limits checked
// on the header before pixels are decoded.
#include "scene/gltf/image_decode.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "encode/encode.h"
#include "encode/jpeg_markers.h"
#include "gltf_test_util.h"

namespace gistream {
namespace image_decode_test {

std::vector<uint8_t> Bytes(const std::string& s) { return {s.begin(), s.end()}; }

std::vector<uint8_t> Png(const std::vector<uint8_t>& rgba, int w, int h) {
  return Bytes(*EncodePng(rgba, w, h));
}

// A 2x1 Radiance HDR file, flat (uncompressed) scanlines.
std::vector<uint8_t> TinyHdr() {
  std::vector<uint8_t> hdr = Bytes("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n");
  // RGBE with exponent 129: value = mantissa / 128.
  hdr.insert(hdr.end(), {128, 64, 32, 129, 0, 0, 128, 131});
  return hdr;
}

TEST(ImageDecode, DetectsFormatsByMagic) {
  EXPECT_EQ(DetectImageFormat(Png({1, 2, 3, 4}, 1, 1)), "png");
  EXPECT_EQ(DetectImageFormat(Bytes(*EncodeJpeg(std::vector<uint8_t>(64, 9), 4, 4, 90))), "jpeg");
  EXPECT_EQ(DetectImageFormat(TinyHdr()), "hdr");
  EXPECT_EQ(DetectImageFormat(Bytes(*EncodeExr(std::vector<float>(4, 1.0f), 1, 1))), "exr");
  EXPECT_EQ(DetectImageFormat(Bytes("BM6\x01\x00")), "");
  EXPECT_EQ(DetectImageFormat({}), "");
}

TEST(ImageDecode, PngTextureKeepsExactPixels) {
  std::vector<uint8_t> rgba(5 * 3 * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t(i * 7);
  const absl::StatusOr<Image> image =
      DecodeImage(Png(rgba, 5, 3), ImageKind::kTexture, {}, "images[0]");
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(image->width, 5);
  EXPECT_EQ(image->height, 3);
  EXPECT_EQ(image->channels, 4);
  EXPECT_TRUE(image->srgb);
  EXPECT_FALSE(image->is_float);
  EXPECT_EQ(image->pixels8, rgba);
}

TEST(ImageDecode, JpegTextureIsOpaqueRgba) {
  const std::vector<uint8_t> rgba(8 * 8 * 4, 128);
  const absl::StatusOr<Image> image =
      DecodeImage(Bytes(*EncodeJpeg(rgba, 8, 8, 95)), ImageKind::kTexture, {}, "images[0]");
  ASSERT_TRUE(image.ok()) << image.status();
  ASSERT_EQ(image->pixels8.size(), 8u * 8 * 4);
  for (size_t i = 0; i < image->pixels8.size(); i += 4) {
    EXPECT_NEAR(image->pixels8[i], 128, 2);
    EXPECT_EQ(image->pixels8[i + 3], 255);
  }
}

TEST(ImageDecode, HdrEnvironmentIsLinearFloat) {
  const absl::StatusOr<Image> image = DecodeImage(TinyHdr(), ImageKind::kEnvironment, {}, "env");
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_TRUE(image->is_float);
  EXPECT_FALSE(image->srgb);
  ASSERT_EQ(image->pixelsf.size(), 8u);
  const float expected[] = {1.0f, 0.5f, 0.25f, 1.0f, 0.0f, 0.0f, 4.0f, 1.0f};
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(image->pixelsf[size_t(i)], expected[i], 1e-6f) << i;
}

TEST(ImageDecode, ExrEnvironmentKeepsFloats) {
  const std::vector<float> rgba = {1e-3f, 1e5f, 0.5f, 1.0f, 2.0f, 3.0f, 4.0f, 1.0f};
  const absl::StatusOr<Image> image =
      DecodeImage(Bytes(*EncodeExr(rgba, 2, 1)), ImageKind::kEnvironment, {}, "env");
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(image->pixelsf, rgba);
}

// Found by tests/fuzz/image_decode_fuzzer: OpenEXR parses a chlist by its
// content, not its size field, so a channel list ending early left it
// reading the next "attribute" mid-value (one claimed 1.9 GB, allocated
// before reading). A value whose content and size disagree is refused.
TEST(ImageDecode, ExrValueThatDisagreesWithItsSizeIsRefused) {
  std::vector<uint8_t> exr = Bytes(*EncodeExr(std::vector<float>(4 * 4, 0.5f), 2, 2));
  const std::string chlist = "channels";
  const auto at = std::search(exr.begin(), exr.end(), chlist.begin(), chlist.end());
  ASSERT_NE(at, exr.end());
  // "channels\0chlist\0", the size, then the first channel's name ("A").
  const size_t value = size_t(at - exr.begin()) + chlist.size() + 1 + 7 + 4;
  const size_t second_name = value + 2 + 16;
  ASSERT_LT(second_name, exr.size());
  ASSERT_NE(exr[second_name], 0) << "the list has a second channel";
  std::vector<uint8_t> forged = exr;
  forged[second_name] = 0;  // the list now ends after one channel
  EXPECT_ERROR(DecodeImage(forged, ImageKind::kEnvironment, {}, "env"), kInvalidArgument,
               "env: corrupt exr image: attribute 'channels' of type chlist holds 19 bytes of "
               "value in a size of");
  EXPECT_TRUE(DecodeImage(exr, ImageKind::kEnvironment, {}, "env").ok());
}

// Found by tests/fuzz/image_decode_fuzzer: OpenEXR sizes its compressor
// from the data window when it opens the file (a 322-byte file with a
// 6.6M-pixel wide window allocated 1.3 GB for ZIP), before the spec
// reaches the limits: the window is held to them in the header walk.
TEST(ImageDecode, ExrDataWindowIsHeldToTheLimitsBeforeOpenExrSizesBuffers) {
  const std::vector<uint8_t> exr = Bytes(*EncodeExr(std::vector<float>(4 * 4, 0.5f), 2, 2));
  const std::string window = std::string("dataWindow") + '\0' + "box2i" + '\0';
  const auto at = std::search(exr.begin(), exr.end(), window.begin(), window.end());
  ASSERT_NE(at, exr.end());
  const size_t xmax = size_t(at - exr.begin()) + window.size() + 4 + 8;
  std::vector<uint8_t> forged = exr;
  const uint32_t wide = 6600000;
  for (int b = 0; b < 4; ++b) forged[xmax + size_t(b)] = uint8_t((wide >> (8 * b)) & 0xff);
  EXPECT_ERROR(DecodeImage(forged, ImageKind::kEnvironment, {}, "env"), kResourceExhausted,
               "env: 6600001x2 pixels exceed the limit of 16384 per side");
  ImportLimits small;
  small.max_image_dimension = 1;
  EXPECT_ERROR(DecodeImage(exr, ImageKind::kEnvironment, small, "env"), kResourceExhausted,
               "env: 2x2 pixels exceed the limit of 1 per side");
  EXPECT_TRUE(DecodeImage(exr, ImageKind::kEnvironment, {}, "env").ok());
}

// Found by tests/fuzz/image_decode_fuzzer: OpenImageIO 2.4's memory reader
// reads at a negative offset from before its buffer, and an EXR's line
// offset table can say -4. Under ASan this read is a heap-buffer-overflow
// without the bounded reader (encode/image_reader.cpp).
TEST(ImageDecode, ExrLineOffsetBeforeTheFileIsAnErrorNotARead) {
  std::vector<uint8_t> exr = Bytes(*EncodeExr(std::vector<float>(4 * 4, 0.5f), 2, 2));
  // Past the header's attributes (name, type, 4-byte size, value) and its
  // terminating NUL: the line offset table, 8 bytes per chunk.
  size_t pos = 8;
  while (exr.at(pos) != 0) {
    pos = size_t(std::find(exr.begin() + long(pos), exr.end(), 0) - exr.begin()) + 1;  // name
    pos = size_t(std::find(exr.begin() + long(pos), exr.end(), 0) - exr.begin()) + 1;  // type
    const uint32_t size = uint32_t(exr.at(pos)) | uint32_t(exr.at(pos + 1)) << 8 |
                          uint32_t(exr.at(pos + 2)) << 16 | uint32_t(exr.at(pos + 3)) << 24;
    pos += 4 + size;
  }
  const size_t table = pos + 1;
  ASSERT_LT(table + 8, exr.size());
  for (size_t b = 0; b < 8; ++b) exr[table + b] = b == 0 ? 0xfc : 0xff;  // -4
  EXPECT_ERROR(DecodeImage(exr, ImageKind::kEnvironment, {}, "env"), kInvalidArgument, "env:");
}

// Found by tests/fuzz/image_decode_fuzzer: libpng allocates a chunk's
// claimed length before reading it (a 470-byte PNG whose tEXt chunk
// claimed 1.7 GB allocated 1.7 GB). The chunks are walked first.
TEST(ImageDecode, PngChunkClaimingMoreThanTheFileIsRefused) {
  const std::vector<uint8_t> png = Png(std::vector<uint8_t>(4 * 4 * 4, 7), 4, 4);
  // After the signature (8) and IHDR (8 + 13 + 4): a tEXt chunk claiming
  // 1,728,053,353 bytes with a few bytes of text.
  const size_t after_ihdr = 8 + 8 + 13 + 4;
  ASSERT_EQ(std::string(png.begin() + 12, png.begin() + 16), "IHDR");
  std::vector<uint8_t> forged(png.begin(), png.begin() + after_ihdr);
  const std::vector<uint8_t> text = {0x67, 0x00, 0x00, 0x69, 't', 'E', 'X', 't', 'a', 0, 'b'};
  forged.insert(forged.end(), text.begin(), text.end());
  forged.insert(forged.end(), png.begin() + after_ihdr, png.end());
  EXPECT_ERROR(DecodeImage(forged, ImageKind::kTexture, {}, "images[0]"), kInvalidArgument,
               "images[0]: corrupt png image: chunk 'tEXt' claims 1728053353 bytes");
  EXPECT_TRUE(DecodeImage(png, ImageKind::kTexture, {}, "images[0]").ok());
}

TEST(ImageDecode, EnvironmentRefusesNonFiniteRadiance) {
  const std::vector<float> rgba = {1, std::numeric_limits<float>::quiet_NaN(), 1, 1};
  EXPECT_ERROR(DecodeImage(Bytes(*EncodeExr(rgba, 1, 1)), ImageKind::kEnvironment, {}, "env"),
               kInvalidArgument, "env: pixel 0 channel 1 is nan");
}

TEST(ImageDecode, EachKindAcceptsOnlyItsFormats) {
  EXPECT_ERROR(DecodeImage(TinyHdr(), ImageKind::kTexture, {}, "images[1]"), kInvalidArgument,
               "images[1]: hdr data where a PNG or JPEG image is expected");
  EXPECT_ERROR(DecodeImage(Png({1, 2, 3, 4}, 1, 1), ImageKind::kEnvironment, {}, "env"),
               kInvalidArgument, "env: png data where a Radiance HDR or OpenEXR image is expected");
  EXPECT_ERROR(DecodeImage(Bytes("GIF89a......"), ImageKind::kTexture, {}, "images[2]"),
               kInvalidArgument, "images[2]: not a PNG or JPEG image (data starts with 47 49 46");
}

TEST(ImageDecode, LimitsAreCheckedOnTheHeader) {
  // Only a header: decoding pixels would fail, so RESOURCE_EXHAUSTED proves
  // the limit was applied first.
  EXPECT_ERROR(DecodeImage(testing::PngHeaderOnly(100000, 100000), ImageKind::kTexture, {}, "img"),
               kResourceExhausted, "img: 100000x100000 pixels exceed the limit of 16384 per side");
  ImportLimits limits;
  limits.max_image_pixels = 100;
  EXPECT_ERROR(DecodeImage(testing::PngHeaderOnly(11, 10), ImageKind::kTexture, limits, "img"),
               kResourceExhausted, "img: 11x10 pixels exceed the limit of 100 pixels");
  limits.max_image_dimension = 8;
  EXPECT_ERROR(DecodeImage(testing::PngHeaderOnly(9, 1), ImageKind::kTexture, limits, "img"),
               kResourceExhausted, "limit of 8 per side");
}

TEST(ImageDecode, CorruptDataIsInvalid) {
  std::vector<uint8_t> png = Png(std::vector<uint8_t>(16 * 16 * 4, 3), 16, 16);
  png.resize(png.size() / 2);
  EXPECT_ERROR(DecodeImage(png, ImageKind::kTexture, {}, "images[0]"), kInvalidArgument,
               "images[0]: corrupt png image");
  EXPECT_ERROR(DecodeImage(Bytes("\x89PNG\r\n\x1a\n"), ImageKind::kTexture, {}, "images[0]"),
               kInvalidArgument, "images[0]: corrupt png image");
  EXPECT_ERROR(DecodeImage(Bytes("\xff\xd8\xff garbage"), ImageKind::kTexture, {}, "images[0]"),
               kInvalidArgument, "images[0]: corrupt jpeg image");
}

// Found by tests/fuzz/image_decode_fuzzer: OpenImageIO 2.4 strcmp()s saved
// APP1/APP13 data, which libjpeg does not terminate, so an APP1 segment of
// two bytes was read past its end (ASan, strict_string_checks). Metadata
// segments are removed before the reader sees the file; under the
// sanitizers this test fails without that.
TEST(ImageDecode, JpegMetadataSegmentsNeverReachTheReader) {
  std::vector<uint8_t> rgba(8 * 8 * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t(i % 4 == 3 ? 255 : (i * 7) % 251);
  const std::vector<uint8_t> clean = Bytes(*EncodeJpeg(rgba, 8, 8, 95));
  ASSERT_GT(clean.size(), 4u);
  ASSERT_EQ(clean[2], 0xFF);
  ASSERT_EQ(clean[3], 0xE0) << "the encoder writes JFIF (APP0) first";
  // After SOI: APP1 "Ex" (no NUL), fill bytes, APP13 of one byte, COM, and
  // an APP15; APP0 (JFIF) and everything else stay.
  const std::vector<uint8_t> metadata = {0xFF, 0xE1, 0x00, 0x04, 'E',  'x',  0xFF, 0xFF,
                                         0xFF, 0xED, 0x00, 0x03, 'P',  0xFF, 0xFE, 0x00,
                                         0x05, 'a',  'b',  'c',  0xFF, 0xEF, 0x00, 0x02};
  std::vector<uint8_t> forged(clean.begin(), clean.begin() + 2);
  forged.insert(forged.end(), metadata.begin(), metadata.end());
  forged.insert(forged.end(), clean.begin() + 2, clean.end());
  EXPECT_EQ(StripJpegMetadata(forged), clean) << "only the metadata segments are removed";
  EXPECT_EQ(StripJpegMetadata(clean), clean);

  const absl::StatusOr<Image> want = DecodeImage(clean, ImageKind::kTexture, {}, "images[0]");
  const absl::StatusOr<Image> got = DecodeImage(forged, ImageKind::kTexture, {}, "images[0]");
  ASSERT_TRUE(want.ok()) << want.status();
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->pixels8, want->pixels8);

  // A segment cut off by the end of the file is copied as it is, and
  // libjpeg refuses the file.
  const std::vector<uint8_t> cut = {0xFF, 0xD8, 0xFF, 0xE1, 0x00};
  EXPECT_EQ(StripJpegMetadata(cut), cut);
  EXPECT_ERROR(DecodeImage(cut, ImageKind::kTexture, {}, "images[0]"), kInvalidArgument,
               "images[0]: corrupt jpeg image");
}

}  // namespace image_decode_test
}  // namespace gistream
