#include "encode/image_format.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <mutex>

namespace gistream {
namespace {

bool StartsWith(std::span<const uint8_t> bytes, std::string_view magic) {
  return bytes.size() >= magic.size() && std::memcmp(bytes.data(), magic.data(), magic.size()) == 0;
}

}  // namespace

std::string_view SniffImageFormat(std::span<const uint8_t> bytes) {
  if (StartsWith(bytes, "\x89PNG\r\n\x1a\n")) return "png";
  if (StartsWith(bytes, "\xff\xd8\xff")) return "jpeg";
  if (StartsWith(bytes, "#?RADIANCE") || StartsWith(bytes, "#?RGBE")) return "hdr";
  if (StartsWith(bytes, std::string_view("\x76\x2f\x31\x01", 4))) return "exr";
  return "";
}

void ConfigureOpenImageIO() {
  static std::once_flag once;
  std::call_once(once, [] { OIIO::attribute("try_all_readers", 0); });
}

std::string HexPrefix(std::span<const uint8_t> bytes, size_t count) {
  std::string out;
  for (size_t i = 0; i < std::min(count, bytes.size()); ++i) {
    char hex[4];
    std::snprintf(hex, sizeof(hex), i == 0 ? "%02x" : " %02x", bytes[i]);
    out += hex;
  }
  return out.empty() ? "no bytes" : out;
}

}  // namespace gistream
