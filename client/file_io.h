// Whole-file reads and writes with errors that name the path.
#pragma once

#include <filesystem>
#include <string>

#include <absl/strings/string_view.h>

#include "util/status.h"

namespace gistream::client {

// NOT_FOUND when missing; the bytes otherwise.
absl::StatusOr<std::string> ReadFile(const std::filesystem::path& path);

// Creates missing parent directories, writes to a temporary name beside
// `path` and renames it into place, so readers never see a partial image.
absl::Status WriteFile(const std::filesystem::path& path, absl::string_view bytes);

}  // namespace gistream::client
