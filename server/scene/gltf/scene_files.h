// File access for scene import: URIs are resolved strictly inside a scene
// directory and files are read with a byte budget.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "util/status.h"

namespace gistream {

// Decodes %XX escapes. INVALID_ARGUMENT for a malformed escape or %00.
absl::StatusOr<std::string> PercentDecode(const std::string& uri, const std::string& field);

// Resolves an already-decoded relative path against `base_dir` (see
// ResolveSceneUri in gltf_import.h, which percent-decodes first).
absl::StatusOr<std::filesystem::path> ResolveScenePath(const std::filesystem::path& base_dir,
                                                       const std::string& path,
                                                       const std::string& field);

// Reads a regular file of at most `max_bytes` bytes. NOT_FOUND when it does
// not exist, RESOURCE_EXHAUSTED when it is larger.
absl::StatusOr<std::vector<uint8_t>> ReadFileLimited(const std::filesystem::path& path,
                                                     uint64_t max_bytes, const std::string& field);

}  // namespace gistream
