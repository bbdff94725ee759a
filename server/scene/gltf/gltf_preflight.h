// Checks on the raw bytes before tinygltf sees them: the GLB container, the
// JSON's syntax, nesting and size, the node count, extensions we must
// understand, external buffer URIs, and the image buffer views that
// tinygltf 2.7 dereferences without a bounds check.
#pragma once

#include <cstdint>
#include <span>

#include "scene/gltf/gltf_import.h"
#include "util/status.h"

namespace gistream::gltf {

struct Container {
  bool binary = false;            // .glb
  std::span<const uint8_t> json;  // the JSON text (the JSON chunk of a .glb)
  uint64_t bin_size = 0;          // the BIN chunk's payload, 0 if none
};

// Tells a .glb from a .gltf and validates the GLB header and chunks.
absl::StatusOr<Container> SplitContainer(std::span<const uint8_t> bytes);

absl::Status PreflightJson(const Container& container, const ImportOptions& options);

}  // namespace gistream::gltf
