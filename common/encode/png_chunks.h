// A structural check of a PNG's chunks before libpng reads it: libpng
// allocates a chunk's claimed length before it reads the chunk (found by
// tests/fuzz/image_decode_fuzzer: a 470-byte PNG whose tEXt chunk claimed
// 1.7 GB allocated 1.7 GB). Every chunk up to IEND must fit in the bytes
// that follow its header.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "util/status.h"

namespace gistream {

// INVALID_ARGUMENT naming `field` and the chunk when one claims more bytes
// than remain; OK for anything that is not PNG (checked elsewhere).
absl::Status CheckPngChunks(std::span<const uint8_t> bytes, const std::string& field);

}  // namespace gistream
