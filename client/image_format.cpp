#include "image_format.h"

#include <absl/strings/ascii.h>
#include <absl/strings/str_cat.h>

namespace gistream::client {

absl::StatusOr<v1::ImageFormat> ParseImageFormat(absl::string_view name) {
  const std::string lower = absl::AsciiStrToLower(name);
  if (lower == "jpeg" || lower == "jpg") return v1::IMAGE_FORMAT_JPEG;
  if (lower == "png") return v1::IMAGE_FORMAT_PNG;
  if (lower == "exr") return v1::IMAGE_FORMAT_EXR;
  return absl::InvalidArgumentError(
      absl::StrCat("unknown image format \"", name, "\" (expected jpeg, png or exr)"));
}

absl::string_view ImageFormatName(v1::ImageFormat format) {
  switch (format) {
    case v1::IMAGE_FORMAT_PNG: return "png";
    case v1::IMAGE_FORMAT_EXR: return "exr";
    default: return "jpeg";
  }
}

absl::string_view ImageFormatExtension(v1::ImageFormat format) {
  switch (format) {
    case v1::IMAGE_FORMAT_PNG: return ".png";
    case v1::IMAGE_FORMAT_EXR: return ".exr";
    default: return ".jpg";
  }
}

std::optional<v1::ImageFormat> ImageFormatFromPath(const std::filesystem::path& path) {
  const std::string ext = absl::AsciiStrToLower(path.extension().string());
  if (ext == ".jpg" || ext == ".jpeg") return v1::IMAGE_FORMAT_JPEG;
  if (ext == ".png") return v1::IMAGE_FORMAT_PNG;
  if (ext == ".exr") return v1::IMAGE_FORMAT_EXR;
  return std::nullopt;
}

}  // namespace gistream::client
