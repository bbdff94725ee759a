// What the image readers and writers share: format detection by magic bytes
// and the one-time OpenImageIO configuration.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace gistream {

// "png", "jpeg", "hdr", "exr", or "" when the magic bytes match none.
std::string_view SniffImageFormat(std::span<const uint8_t> bytes);

// Applies process-wide OpenImageIO settings once (thread-safe): readers are
// chosen by us, never by OIIO trying every plugin on unknown data.
void ConfigureOpenImageIO();

// The first bytes as hex ("42 4d 36 00"), for messages about unknown data.
std::string HexPrefix(std::span<const uint8_t> bytes, size_t count = 8);

}  // namespace gistream
