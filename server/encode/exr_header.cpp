#include "encode/exr_header.h"

#include <algorithm>
#include <cstring>

namespace gistream {
namespace {

constexpr uint8_t kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
constexpr uint32_t kMultiPartFlag = 0x1000;  // version field bit 12
constexpr size_t kMaxName = 256;

// A NUL-terminated string of at most kMaxName bytes at `pos`; advances past
// the NUL. False when it runs off the end or is too long.
bool ReadName(std::span<const uint8_t> bytes, size_t& pos, std::string* out) {
  const size_t end = std::min(bytes.size(), pos + kMaxName + 1);
  for (size_t i = pos; i < end; ++i) {
    if (bytes[i] == 0) {
      out->assign(reinterpret_cast<const char*>(bytes.data() + pos), i - pos);
      pos = i + 1;
      return true;
    }
  }
  return false;
}

}  // namespace

absl::Status CheckExrHeader(std::span<const uint8_t> bytes, const std::string& field) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 4) != 0) return absl::OkStatus();
  const uint32_t version = uint32_t(bytes[4]) | uint32_t(bytes[5]) << 8 | uint32_t(bytes[6]) << 16 |
                           uint32_t(bytes[7]) << 24;
  const bool multi_part = (version & kMultiPartFlag) != 0;
  auto corrupt = [&](const std::string& why) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": corrupt exr image: ", why));
  };
  size_t pos = 8;
  for (int part = 0;; ++part) {
    // A multi-part file ends its list of headers with an empty one.
    if (multi_part && part > 0) {
      if (pos >= bytes.size()) return corrupt("the list of part headers is not terminated");
      if (bytes[pos] == 0) return absl::OkStatus();
    }
    for (;;) {
      if (pos >= bytes.size()) return corrupt(absl::StrCat("header ", part, " is not terminated"));
      if (bytes[pos] == 0) {
        ++pos;
        break;
      }
      std::string name, type;
      if (!ReadName(bytes, pos, &name) || !ReadName(bytes, pos, &type)) {
        return corrupt(absl::StrCat("an attribute name or type of header ", part,
                                    " is longer than ", kMaxName, " bytes or not terminated"));
      }
      if (bytes.size() - pos < 4)
        return corrupt(absl::StrCat("attribute '", name, "' has no size"));
      const int32_t size = int32_t(uint32_t(bytes[pos]) | uint32_t(bytes[pos + 1]) << 8 |
                                   uint32_t(bytes[pos + 2]) << 16 | uint32_t(bytes[pos + 3]) << 24);
      pos += 4;
      if (size < 0 || uint64_t(size) > bytes.size() - pos) {
        return corrupt(absl::StrCat("attribute '", name, "' claims ", size, " bytes, ",
                                    bytes.size() - pos, " remain"));
      }
      pos += size_t(size);
    }
    if (!multi_part) return absl::OkStatus();
  }
}

}  // namespace gistream
