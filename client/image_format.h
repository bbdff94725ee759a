// Names and file extensions of the image formats frames can carry.
#pragma once

#include <filesystem>
#include <optional>

#include <absl/strings/string_view.h>

#include "gistream/v1/gistream.pb.h"
#include "util/status.h"

namespace gistream::client {

// "jpeg" (or "jpg"), "png", "exr", "h264", "hevc" (or "h265"), "av1";
// INVALID_ARGUMENT names the choices.
absl::StatusOr<v1::ImageFormat> ParseImageFormat(absl::string_view name);

// "jpeg", "png", "exr", "h264", "hevc", "av1"; UNSPECIFIED is JPEG, as on
// the server.
absl::string_view ImageFormatName(v1::ImageFormat format);

// ".jpg", ".png", ".exr", ".h264", ".hevc", ".obu" (AV1 low-overhead OBUs,
// which ffmpeg reads as format "obu").
absl::string_view ImageFormatExtension(v1::ImageFormat format);

// The format a file name's extension implies, if any (".jpg", ".jpeg",
// ".png", ".exr", in any case).
std::optional<v1::ImageFormat> ImageFormatFromPath(const std::filesystem::path& path);

// H264, HEVC, AV1: a stream of access units, not one image per frame.
bool IsVideoFormat(v1::ImageFormat format);

}  // namespace gistream::client
