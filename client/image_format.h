// Names and file extensions of the image formats frames can carry.
#pragma once

#include <filesystem>
#include <optional>

#include <absl/strings/string_view.h>

#include "gistream/v1/gistream.pb.h"
#include "util/status.h"

namespace gistream::client {

// "jpeg" (or "jpg"), "png", "exr"; INVALID_ARGUMENT names the choices.
absl::StatusOr<v1::ImageFormat> ParseImageFormat(absl::string_view name);

// "jpeg", "png", "exr"; UNSPECIFIED is JPEG, as on the server.
absl::string_view ImageFormatName(v1::ImageFormat format);

// ".jpg", ".png", ".exr".
absl::string_view ImageFormatExtension(v1::ImageFormat format);

// The format a file name's extension implies, if any (".jpg", ".jpeg",
// ".png", ".exr", in any case).
std::optional<v1::ImageFormat> ImageFormatFromPath(const std::filesystem::path& path);

}  // namespace gistream::client
