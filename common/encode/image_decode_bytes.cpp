// DecodeImageBytes: client- and test-side decoding of what the encoders
// produce (and of PNG/JPEG/EXR/HDR in general), from memory.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <vector>

#include "encode/encode.h"
#include "encode/image_format.h"
#include "encode/image_reader.h"

namespace gistream {
namespace {
// Frames and test images are far below this; it bounds what a hostile
// header can make us allocate.
constexpr uint64_t kMaxDecodePixels = 1ull << 28;
}  // namespace

absl::StatusOr<DecodedImage> DecodeImageBytes(std::span<const uint8_t> bytes) {
  ConfigureOpenImageIO();
  const std::string format(SniffImageFormat(bytes));
  if (format.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat("image: unknown format (starts with ", HexPrefix(bytes), ")"));
  }
  GS_ASSIGN_OR_RETURN(MemoryImageReader reader, OpenImageFromMemory(bytes, format, "image"));
  const OIIO::ImageSpec& spec = reader.spec;
  OIIO::ImageInput* in = reader.input.get();
  const uint64_t pixels = static_cast<uint64_t>(spec.width) * static_cast<uint64_t>(spec.height);
  if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1 || spec.nchannels <= 0 ||
      pixels > kMaxDecodePixels) {
    return absl::InvalidArgumentError(absl::StrCat("image: unsupported size ", spec.width, "x",
                                                   spec.height, "x", spec.nchannels));
  }
  const int channels = std::min(spec.nchannels, 4);
  std::vector<float> raw(pixels * static_cast<uint64_t>(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, raw.data())) {
    return absl::InvalidArgumentError(
        absl::StrCat("image: corrupt ", format, " data: ", in->geterror()));
  }
  DecodedImage out;
  out.width = spec.width;
  out.height = spec.height;
  out.rgba.resize(pixels * 4);
  for (uint64_t p = 0; p < pixels; ++p) {
    const float* src = &raw[p * static_cast<uint64_t>(channels)];
    float* dst = &out.rgba[p * 4];
    const bool gray = channels <= 2;
    dst[0] = src[0];
    dst[1] = gray ? src[0] : src[1];
    dst[2] = gray ? src[0] : src[2];
    dst[3] = channels == 2 ? src[1] : channels == 4 ? src[3] : 1.0f;
  }
  return out;
}

}  // namespace gistream
