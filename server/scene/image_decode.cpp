#include "scene/image_decode.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "encode/image_format.h"
#include "encode/image_reader.h"

namespace gistream {
namespace {

bool KindAccepts(ImageKind kind, const std::string& format) {
  if (kind == ImageKind::kTexture) return format == "png" || format == "jpeg";
  return format == "hdr" || format == "exr";
}

const char* KindFormats(ImageKind kind) {
  return kind == ImageKind::kTexture ? "PNG or JPEG" : "Radiance HDR or OpenEXR";
}

absl::Status CheckSpec(const OIIO::ImageSpec& spec, const ImportLimits& limits,
                       const std::string& field) {
  if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1 || spec.nchannels <= 0) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": invalid image size ", spec.width, "x",
                                                   spec.height, "x", spec.depth, " with ",
                                                   spec.nchannels, " channels"));
  }
  const uint64_t w = static_cast<uint64_t>(spec.width);
  const uint64_t h = static_cast<uint64_t>(spec.height);
  if (w > limits.max_image_dimension || h > limits.max_image_dimension) {
    return absl::ResourceExhaustedError(absl::StrCat(field, ": ", w, "x", h,
                                                     " pixels exceed the limit of ",
                                                     limits.max_image_dimension, " per side"));
  }
  uint64_t pixels = 0;
  uint64_t values = 0;
  if (__builtin_mul_overflow(w, h, &pixels) || pixels > limits.max_image_pixels ||
      __builtin_mul_overflow(pixels, uint64_t{4}, &values)) {
    return absl::ResourceExhaustedError(absl::StrCat(field, ": ", w, "x", h,
                                                     " pixels exceed the limit of ",
                                                     limits.max_image_pixels, " pixels"));
  }
  return absl::OkStatus();
}

// Expands 1..4 channels to RGBA; gray replicates, missing alpha is opaque.
template <typename T>
std::vector<T> ToRgba(const std::vector<T>& raw, size_t pixels, int channels, T opaque) {
  std::vector<T> out(pixels * 4);
  for (size_t p = 0; p < pixels; ++p) {
    const T* src = &raw[p * static_cast<size_t>(channels)];
    T* dst = &out[p * 4];
    const bool gray = channels <= 2;
    dst[0] = src[0];
    dst[1] = gray ? src[0] : src[1];
    dst[2] = gray ? src[0] : src[2];
    dst[3] = channels == 2 ? src[1] : channels >= 4 ? src[3] : opaque;
  }
  return out;
}

}  // namespace

std::string DetectImageFormat(std::span<const uint8_t> bytes) {
  return std::string(SniffImageFormat(bytes));
}

absl::StatusOr<Image> DecodeImage(std::span<const uint8_t> bytes, ImageKind kind,
                                  const ImportLimits& limits, const std::string& field) {
  ConfigureOpenImageIO();
  const std::string format = DetectImageFormat(bytes);
  if (format.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(
        field, ": not a ", KindFormats(kind), " image (data starts with ", HexPrefix(bytes), ")"));
  }
  if (!KindAccepts(kind, format)) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": ", format, " data where a ",
                                                   KindFormats(kind), " image is expected"));
  }

  // Only the reader for the detected format is created, and it reads from
  // memory: no file system, no other plugin sees the bytes.
  GS_ASSIGN_OR_RETURN(MemoryImageReader reader, OpenImageFromMemory(bytes, format, field));
  const OIIO::ImageSpec& spec = reader.spec;
  OIIO::ImageInput* in = reader.input.get();
  GS_RETURN_IF_ERROR(CheckSpec(spec, limits, field));

  const size_t pixels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  const int channels = std::min(spec.nchannels, 4);
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = 4;
  if (kind == ImageKind::kTexture) {
    std::vector<uint8_t> raw(pixels * static_cast<size_t>(channels));
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, raw.data())) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": corrupt ", format, " image: ", in->geterror()));
    }
    image.srgb = true;
    image.is_float = false;
    image.pixels8 = ToRgba<uint8_t>(raw, pixels, channels, 255);
  } else {
    std::vector<float> raw(pixels * static_cast<size_t>(channels));
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, raw.data())) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": corrupt ", format, " image: ", in->geterror()));
    }
    for (size_t i = 0; i < raw.size(); ++i) {
      if (!std::isfinite(raw[i])) {
        return absl::InvalidArgumentError(absl::StrCat(
            field, ": pixel ", i / static_cast<size_t>(channels), " channel ",
            i % static_cast<size_t>(channels), " is ", raw[i], "; radiance must be finite"));
      }
      // Filtered HDR captures carry tiny negative lobes; radiance cannot be
      // negative.
      raw[i] = std::max(raw[i], 0.0f);
    }
    image.srgb = false;
    image.is_float = true;
    image.pixelsf = ToRgba<float>(raw, pixels, channels, 1.0f);
  }
  return image;
}

}  // namespace gistream
