#include "encode/jpeg_markers.h"

#include <algorithm>

namespace gistream {
namespace {

// Markers with no length field: TEM, RSTn, SOI, EOI (ITU T.81 B.1.1.3).
bool Standalone(uint8_t code) { return code == 0x01 || (code >= 0xD0 && code <= 0xD9); }

// APP1..APP13, APP15 and COM: metadata the decoder does not need.
bool Metadata(uint8_t code) {
  return (code >= 0xE1 && code <= 0xED) || code == 0xEF || code == 0xFE;
}

}  // namespace

std::vector<uint8_t> StripJpegMetadata(std::span<const uint8_t> bytes) {
  std::vector<uint8_t> out;
  out.reserve(bytes.size());
  const size_t n = bytes.size();
  size_t i = 0;
  while (i < n) {
    if (bytes[i] != 0xFF) {
      out.push_back(bytes[i++]);
      continue;
    }
    // 0xFF, any fill bytes, then the marker code.
    size_t code_at = i + 1;
    while (code_at < n && bytes[code_at] == 0xFF) ++code_at;
    if (code_at >= n) break;  // fill bytes at the end: nothing to decode
    const uint8_t code = bytes[code_at];
    if (code == 0x00 || Standalone(code)) {
      // Stuffed data byte or a marker without a segment.
      out.insert(out.end(), bytes.begin() + i, bytes.begin() + code_at + 1);
      i = code_at + 1;
      continue;
    }
    if (code_at + 2 >= n) {
      out.insert(out.end(), bytes.begin() + i, bytes.end());
      break;
    }
    // The length counts its own two bytes, not the marker.
    const size_t length = (size_t(bytes[code_at + 1]) << 8) | bytes[code_at + 2];
    const size_t end = std::min(n, code_at + 1 + std::max<size_t>(length, 2));
    if (!Metadata(code)) out.insert(out.end(), bytes.begin() + i, bytes.begin() + end);
    i = end;
  }
  return out;
}

}  // namespace gistream
