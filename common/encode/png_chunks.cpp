#include "encode/png_chunks.h"

#include <cstring>

namespace gistream {
namespace {

constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

std::string ChunkType(std::span<const uint8_t> bytes, size_t pos) {
  std::string type;
  for (size_t i = 0; i < 4; ++i) {
    const uint8_t c = bytes[pos + i];
    type += (c >= 0x20 && c < 0x7f) ? char(c) : '?';
  }
  return type;
}

}  // namespace

absl::Status CheckPngChunks(std::span<const uint8_t> bytes, const std::string& field) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0) return absl::OkStatus();
  // Each chunk: length (4 bytes, big-endian), type (4), data, CRC (4).
  size_t pos = 8;
  while (bytes.size() - pos >= 8) {
    const uint64_t length = uint64_t(bytes[pos]) << 24 | uint64_t(bytes[pos + 1]) << 16 |
                            uint64_t(bytes[pos + 2]) << 8 | uint64_t(bytes[pos + 3]);
    const std::string type = ChunkType(bytes, pos + 4);
    const uint64_t remain = bytes.size() - pos - 8;
    if (length + 4 > remain) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": corrupt png image: chunk '", type,
                                                     "' claims ", length, " bytes, ",
                                                     remain < 4 ? 0 : remain - 4, " remain"));
    }
    if (type == "IEND") return absl::OkStatus();
    pos += 8 + size_t(length) + 4;
  }
  // A file cut between chunks is left to libpng's error.
  return absl::OkStatus();
}

}  // namespace gistream
