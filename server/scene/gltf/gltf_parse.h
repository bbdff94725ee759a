// Runs tinygltf on pre-flighted bytes. tinygltf never touches the file
// system itself: external buffers come through FsCallbacks that resolve
// inside ImportOptions::base_dir and charge a byte budget, and images are
// kept encoded (data: URIs) or left for us to read (buffer views, files).
#pragma once

#include <cstdint>
#include <span>

#include "scene/gltf/gltf_import.h"
#include "scene/gltf/gltf_preflight.h"
#include "scene/gltf/tinygltf.h"
#include "util/status.h"

namespace gistream::gltf {

// `budget` is the number of bytes external files may still add; it is
// reduced by what is read.
absl::StatusOr<tinygltf::Model> ParseModel(std::span<const uint8_t> bytes,
                                           const Container& container, const ImportOptions& options,
                                           uint64_t* budget);

}  // namespace gistream::gltf
