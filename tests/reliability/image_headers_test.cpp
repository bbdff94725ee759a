// Issue 13, finding 2 (unbounded memory), image part: a 92-byte HDR header
// claiming 16384 x 4096 pixels cost 758 MB before it was refused.
#include <gtest/gtest.h>

#include <span>
#include <string>
#include <vector>

#include "encode/encode.h"
#include "reliability/reliability_fixture.h"
#include "scene/gltf/image_decode.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace image_headers_test {

std::string ForgedHdr(int width, int height) {
  return absl::StrCat("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y ", height, " +X ", width, "\n",
                      std::string(16, '\x02'));
}

TEST(ImageHeaders, ForgedHdrHeaderIsRefusedBeforeAllocating) {
  // 16384 x 4096 is exactly the default pixel limit (8192^2): the header
  // passes the limit, and decoding used to allocate 758 MB before finding
  // the data missing.
  const std::string hdr = ForgedHdr(16384, 4096);
  ASSERT_LT(hdr.size(), 100u);
  const std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(hdr.data()), hdr.size());
  const bool can_measure = ResetPeakRss();
  const uint64_t before = StatusKiB("VmRSS");
  EXPECT_STATUS(
      StatusOf(DecodeImage(bytes, ImageKind::kEnvironment, ImportLimits{}, "environment")),
      kInvalidArgument, "environment: truncated hdr image: the header claims 16384x4096");
  if (can_measure) {
    // 64 MiB: far below the 1 GiB the claimed pixels would take as RGBA floats.
    EXPECT_LT(StatusKiB("VmHWM"), before + 64 * 1024) << "peak RSS grew while refusing";
  }
  // Over the limit, it is RESOURCE_EXHAUSTED from the header alone.
  const std::string big = ForgedHdr(16384, 8192);
  EXPECT_STATUS(StatusOf(DecodeImage(std::span<const uint8_t>(
                                         reinterpret_cast<const uint8_t*>(big.data()), big.size()),
                                     ImageKind::kEnvironment, ImportLimits{}, "environment")),
                kResourceExhausted, "pixels exceed the limit");
  // Through the engine: refused, and the engine loads a real map next.
  SceneSource source = testing::SceneFromBytes(QuadScene().dump());
  source.environment_bytes = hdr;
  EXPECT_STATUS(StatusOf(E().LoadScene(source)), kInvalidArgument, "truncated hdr image");
  auto exr = EncodeExr(std::vector<float>(8 * 4 * 4, 0.25f), 8, 4);
  ASSERT_TRUE(exr.ok());
  source.environment_bytes = *exr;
  auto info = E().LoadScene(source);
  ASSERT_TRUE(info.ok()) << info.status();
  ExpectRendersFinite(info->id, "direct");
  EXPECT_TRUE(E().UnloadScene(info->id).ok());
}

// Found by tests/fuzz/image_decode_fuzzer: OpenEXR allocates what a
// header attribute claims before it finds the file too short (a 721-byte
// file whose string attribute claimed 1.8 GB allocated 1.8 GB). The header
// is walked first (encode/exr_header.h).
TEST(ImageHeaders, ExrAttributeClaimingMoreThanTheFileIsRefusedBeforeAllocating) {
  auto exr = EncodeExr(std::vector<float>(4 * 3 * 4, 0.5f), 4, 3);
  ASSERT_TRUE(exr.ok()) << exr.status();
  std::string forged = *exr;
  // The first attribute's size follows its name and type name.
  size_t pos = 8;
  pos = forged.find('\0', pos) + 1;  // name
  const std::string name = forged.substr(8, pos - 9);
  pos = forged.find('\0', pos) + 1;  // type
  const uint32_t claimed = 1845493869;
  for (int b = 0; b < 4; ++b) forged[pos + size_t(b)] = char((claimed >> (8 * b)) & 0xff);
  const std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(forged.data()),
                                       forged.size());
  const bool can_measure = ResetPeakRss();
  const uint64_t before = StatusKiB("VmRSS");
  EXPECT_STATUS(
      StatusOf(DecodeImage(bytes, ImageKind::kEnvironment, ImportLimits{}, "environment")),
      kInvalidArgument,
      absl::StrCat("environment: corrupt exr image: attribute '", name,
                   "' claims 1845493869 bytes"));
  if (can_measure) {
    EXPECT_LT(StatusKiB("VmHWM"), before + 64 * 1024) << "peak RSS grew while refusing";
  }
  // The unforged file still decodes.
  auto image = DecodeImage(
      std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(exr->data()), exr->size()),
      ImageKind::kEnvironment, ImportLimits{}, "environment");
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(image->width, 4);
}

}  // namespace image_headers_test
}  // namespace gistream::reliability
