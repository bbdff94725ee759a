// A structural check of an OpenEXR header before OpenEXR reads it: OpenEXR
// 3.1 allocates each attribute's claimed size before it finds the file too
// short (found by tests/fuzz/image_decode_fuzzer: a 721-byte file whose
// string attribute claims 1.8 GB allocated 1.8 GB). Every attribute's size
// must fit in the bytes that follow it, names and type names must be
// terminated within 256 bytes, and the header (every part's, for a
// multi-part file) must end inside the data.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "util/status.h"

namespace gistream {

// What OpenEXR sizes its buffers by when it opens a file, before the
// caller sees the spec: the data window (line buffers, ZIP/PIZ/DWA
// compressors: a width times up to 256 lines), the tile size and the
// channel count.
struct ExrHeaderLimits {
  uint32_t max_dimension = 16384;  // data window and tile, per side
  int max_channels = 16;
};

// INVALID_ARGUMENT naming `field` and the attribute when the header does
// not fit, RESOURCE_EXHAUSTED when its data window is over
// `limits.max_dimension`; OK for anything that is not EXR (checked
// elsewhere).
absl::Status CheckExrHeader(std::span<const uint8_t> bytes, const std::string& field,
                            const ExrHeaderLimits& limits = {});

}  // namespace gistream
