#include "image_format.h"

#include <absl/strings/ascii.h>
#include <absl/strings/str_cat.h>

namespace gistream::client {

absl::StatusOr<v1::ImageFormat> ParseImageFormat(absl::string_view name) {
  const std::string lower = absl::AsciiStrToLower(name);
  if (lower == "jpeg" || lower == "jpg") return v1::IMAGE_FORMAT_JPEG;
  if (lower == "png") return v1::IMAGE_FORMAT_PNG;
  if (lower == "exr") return v1::IMAGE_FORMAT_EXR;
  if (lower == "h264") return v1::IMAGE_FORMAT_H264;
  if (lower == "hevc" || lower == "h265") return v1::IMAGE_FORMAT_HEVC;
  if (lower == "av1") return v1::IMAGE_FORMAT_AV1;
  return absl::InvalidArgumentError(absl::StrCat(
      "unknown image format \"", name, "\" (expected jpeg, png, exr, h264, hevc or av1)"));
}

absl::string_view ImageFormatName(v1::ImageFormat format) {
  switch (format) {
    case v1::IMAGE_FORMAT_PNG: return "png";
    case v1::IMAGE_FORMAT_EXR: return "exr";
    case v1::IMAGE_FORMAT_H264: return "h264";
    case v1::IMAGE_FORMAT_HEVC: return "hevc";
    case v1::IMAGE_FORMAT_AV1: return "av1";
    default: return "jpeg";
  }
}

absl::string_view ImageFormatExtension(v1::ImageFormat format) {
  switch (format) {
    case v1::IMAGE_FORMAT_PNG: return ".png";
    case v1::IMAGE_FORMAT_EXR: return ".exr";
    case v1::IMAGE_FORMAT_H264: return ".h264";
    case v1::IMAGE_FORMAT_HEVC: return ".hevc";
    case v1::IMAGE_FORMAT_AV1: return ".obu";
    default: return ".jpg";
  }
}

std::optional<v1::ImageFormat> ImageFormatFromPath(const std::filesystem::path& path) {
  const std::string ext = absl::AsciiStrToLower(path.extension().string());
  if (ext == ".jpg" || ext == ".jpeg") return v1::IMAGE_FORMAT_JPEG;
  if (ext == ".png") return v1::IMAGE_FORMAT_PNG;
  if (ext == ".exr") return v1::IMAGE_FORMAT_EXR;
  if (ext == ".h264" || ext == ".264") return v1::IMAGE_FORMAT_H264;
  if (ext == ".hevc" || ext == ".h265") return v1::IMAGE_FORMAT_HEVC;
  if (ext == ".obu") return v1::IMAGE_FORMAT_AV1;
  return std::nullopt;
}

bool IsVideoFormat(v1::ImageFormat format) {
  return format == v1::IMAGE_FORMAT_H264 || format == v1::IMAGE_FORMAT_HEVC ||
         format == v1::IMAGE_FORMAT_AV1;
}

}  // namespace gistream::client
