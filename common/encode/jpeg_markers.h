// Removes a JPEG's metadata segments before OpenImageIO reads it.
// OpenImageIO 2.4's JPEG reader compares saved APP1/APP13 marker data to
// "Exif", "http://ns.adobe.com/xap/1.0/" and "Photoshop 3.0" with strcmp,
// but libjpeg keeps marker data exactly as long as the segment, with no
// terminating NUL: an APP1 segment of a few bytes is read past its end
// (found by tests/fuzz/image_decode_fuzzer under ASan). A texture needs
// none of that metadata, so it never reaches the reader.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace gistream {

// A copy of `bytes` without APP1..APP13, APP15 and COM segments, wherever
// they are (before the first scan or between scans). APP0 (JFIF) and APP14
// (Adobe colour transform), which libjpeg itself parses, are kept, and so
// is everything else byte for byte: the walk follows libjpeg's own marker
// scan (bytes before a marker skipped, 0xFF fill, stuffed 0xFF00 and
// restart markers in entropy-coded data), so a segment libjpeg would read
// is a segment this walk sees. A truncated segment is copied as it is and
// left to libjpeg's error.
std::vector<uint8_t> StripJpegMetadata(std::span<const uint8_t> bytes);

}  // namespace gistream
