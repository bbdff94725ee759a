#include "scene/gltf/image_decode.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <type_traits>
#include <cmath>
#include <vector>

#include "encode/image_format.h"
#include "encode/image_reader.h"
#include "scene/magnitude_limits.h"

namespace gistream {
namespace {

bool KindAccepts(ImageKind kind, const std::string& format) {
  if (kind == ImageKind::kTexture) return format == "png" || format == "jpeg";
  return format == "hdr" || format == "exr";
}

const char* KindFormats(ImageKind kind) {
  return kind == ImageKind::kTexture ? "PNG or JPEG" : "Radiance HDR or OpenEXR";
}

// Readers decode every channel of a band of rows before picking RGBA: a
// header naming thousands of channels (a few bytes each in EXR) would
// multiply every band's buffer.
constexpr int kMaxChannels = 16;

absl::Status CheckSpec(const OIIO::ImageSpec& spec, const ImportLimits& limits,
                       const std::string& field) {
  if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1 || spec.nchannels <= 0) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": invalid image size ", spec.width, "x",
                                                   spec.height, "x", spec.depth, " with ",
                                                   spec.nchannels, " channels"));
  }
  if (spec.nchannels > kMaxChannels) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": ", spec.nchannels,
                                                   " channels; at most ", kMaxChannels,
                                                   " are accepted (RGBA is used)"));
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

// Most pixels one encoded byte of each format can describe: far above
// what any encoder reaches (PNG: deflate's 1032:1 on 1-bit pixels is 8256;
// Radiance RLE: 127-pixel runs of 2 bytes per channel are 16; JPEG and
// EXR: a few bits per 8x8 block, less with arithmetic coding or DWA).
// A header that claims more pixels than its file can hold is truncated or
// forged, and is refused before any pixel buffer is allocated (a 92-byte
// HDR header claiming 16384 x 4096 pixels used to allocate 758 MB).
uint64_t MaxPixelsPerByte(const std::string& format) {
  if (format == "hdr") return 1024;
  if (format == "png") return 16384;
  return 65536;  // jpeg, exr
}

absl::Status CheckPlausibleSize(const OIIO::ImageSpec& spec, size_t encoded_bytes,
                                const std::string& format, const std::string& field) {
  const uint64_t pixels = uint64_t(spec.width) * uint64_t(spec.height);
  const uint64_t most = uint64_t(encoded_bytes) * MaxPixelsPerByte(format);
  if (pixels > most) {
    return absl::InvalidArgumentError(absl::StrCat(
        field, ": truncated ", format, " image: the header claims ", spec.width, "x", spec.height,
        " pixels but the data is only ", encoded_bytes, " bytes (at most ", most, " pixels)"));
  }
  return absl::OkStatus();
}

// Reads the image straight into RGBA (gray replicated, missing alpha
// opaque), a band of rows at a time: no second full-size buffer, and a
// file that ends early fails after touching only the rows it really has.
template <typename T>
absl::StatusOr<std::vector<T>> ReadRgba(OIIO::ImageInput* in, const OIIO::ImageSpec& spec,
                                        int channels, T opaque, const std::string& format,
                                        const std::string& field) {
  const size_t width = static_cast<size_t>(spec.width);
  const size_t row = width * 4;
  const OIIO::TypeDesc type =
      std::is_same_v<T, float> ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  constexpr int kBand = 64;
  std::vector<T> out;
  // Address space only: pages are touched band by band as rows decode.
  out.reserve(row * static_cast<size_t>(spec.height));
  for (int y0 = 0; y0 < spec.height; y0 += kBand) {
    const int y1 = std::min(spec.height, y0 + kBand);
    const size_t first = out.size();
    out.resize(row * static_cast<size_t>(y1));
    T* dst = out.data() + first;
    if (!in->read_scanlines(0, 0, spec.y + y0, spec.y + y1, 0, 0, channels, type, dst,
                            OIIO::stride_t(4 * sizeof(T)), OIIO::stride_t(row * sizeof(T)))) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": corrupt ", format, " image: ", in->geterror()));
    }
    for (size_t p = first / 4; p < out.size() / 4; ++p) {
      T* px = &out[p * 4];
      if (channels <= 2) {
        if (channels == 2) px[3] = px[1];
        px[1] = px[0];
        px[2] = px[0];
      }
      if (channels == 1 || channels == 3) px[3] = opaque;
    }
  }
  return out;
}

}  // namespace

std::string DetectImageFormat(std::span<const uint8_t> bytes) {
  return std::string(SniffImageFormat(bytes));
}

absl::StatusOr<Image> DecodeImage(std::span<const uint8_t> bytes, ImageKind kind,
                                  const ImportLimits& limits, const std::string& field,
                                  ImportMemory* memory) {
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
  GS_ASSIGN_OR_RETURN(MemoryImageReader reader,
                      OpenImageFromMemory(bytes, format, field,
                                          {.max_dimension = limits.max_image_dimension,
                                           .max_channels = kMaxChannels}));
  const OIIO::ImageSpec& spec = reader.spec;
  OIIO::ImageInput* in = reader.input.get();
  GS_RETURN_IF_ERROR(CheckSpec(spec, limits, field));

  GS_RETURN_IF_ERROR(CheckPlausibleSize(spec, bytes.size(), format, field));

  const size_t pixels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  if (memory != nullptr) {
    // RGBA, 8-bit or float (ReadRgba's one buffer).
    const uint64_t decoded =
        uint64_t(pixels) * 4 * (kind == ImageKind::kTexture ? sizeof(uint8_t) : sizeof(float));
    GS_RETURN_IF_ERROR(memory->Reserve(
        decoded, absl::StrCat(field, ": ", spec.width, "x", spec.height, " decoded pixels")));
  }
  const int channels = std::min(spec.nchannels, 4);
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = 4;
  if (kind == ImageKind::kTexture) {
    GS_ASSIGN_OR_RETURN(image.pixels8,
                        ReadRgba<uint8_t>(in, spec, channels, uint8_t{255}, format, field));
    image.srgb = true;
    image.is_float = false;
  } else {
    GS_ASSIGN_OR_RETURN(std::vector<float> rgba,
                        ReadRgba<float>(in, spec, channels, 1.0f, format, field));
    for (size_t p = 0; p < pixels; ++p) {
      for (int c = 0; c < 3; ++c) {  // RGB after expansion; alpha is no radiance
        float& v = rgba[p * 4 + size_t(c)];
        if (!std::isfinite(v)) {
          return absl::InvalidArgumentError(absl::StrCat(field, ": pixel ", p, " channel ", c,
                                                         " is ", v, "; radiance must be finite"));
        }
        // Radiance cannot be negative: a map with negative pixels is broken.
        // Filtered HDR captures carry tiny negative ringing, which is clamped.
        if (v < -kNegativeRadianceTolerance) {
          return absl::InvalidArgumentError(absl::StrCat(
              field, ": pixel ", p, " channel ", c, " is ", v,
              "; radiance must not be negative (tolerance ", kNegativeRadianceTolerance, ")"));
        }
        if (v > kMaxRadiance) {
          return absl::InvalidArgumentError(
              absl::StrCat(field, ": pixel ", p, " channel ", c, " is ", v,
                           "; radiance exceeds the limit of ", kMaxRadiance, " nits"));
        }
        v = std::max(v, 0.0f);
      }
    }
    image.srgb = false;
    image.is_float = true;
    image.pixelsf = std::move(rgba);
  }
  return image;
}

}  // namespace gistream
