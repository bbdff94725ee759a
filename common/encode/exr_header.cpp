#include "encode/exr_header.h"

#include <algorithm>
#include <cstring>

namespace gistream {
namespace {

constexpr uint8_t kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
constexpr uint32_t kMultiPartFlag = 0x1000;  // version field bit 12
// OpenEXR reads a name of at most 255 characters and its NUL (Xdr::read
// with Name::MAX_LENGTH): a longer one leaves its reader mid-string.
constexpr size_t kMaxName = 255;

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

uint32_t Le32(std::span<const uint8_t> bytes, size_t pos) {
  return uint32_t(bytes[pos]) | uint32_t(bytes[pos + 1]) << 8 | uint32_t(bytes[pos + 2]) << 16 |
         uint32_t(bytes[pos + 3]) << 24;
}

// The size OpenEXR 3.1's typed attribute of `type` reads whatever the
// attribute's size field says; 0 for types that read their size field.
size_t FixedValueSize(const std::string& type) {
  struct Fixed {
    const char* type;
    size_t size;
  };
  // clang-format off
  static constexpr Fixed kFixed[] = {
      {"box2i", 16}, {"box2f", 16}, {"chromaticities", 32}, {"compression", 1},
      {"double", 8}, {"envmap", 1}, {"float", 4}, {"int", 4}, {"keycode", 28},
      {"lineOrder", 1}, {"m33f", 36}, {"m33d", 72}, {"m44f", 64}, {"m44d", 128},
      {"rational", 8}, {"tiledesc", 9}, {"timecode", 8}, {"v2i", 8}, {"v2f", 8},
      {"v2d", 16}, {"v3i", 12}, {"v3f", 12}, {"v3d", 24}, {"deepImageState", 1},
  };
  // clang-format on
  for (const Fixed& f : kFixed) {
    if (type == f.type) return f.size;
  }
  return 0;
}

// A chlist value: channels, each a name, then pixel type, pLinear + 3
// reserved, x and y sampling (4 bytes each); an empty name ends the list.
// The bytes read, or -1 when the list runs past the value; the channel
// count in `channels` when given.
int64_t WalkChannels(std::span<const uint8_t> value, int* channels) {
  size_t pos = 0;
  for (int n = 0;; ++n) {
    if (pos >= value.size()) return -1;
    if (value[pos] == 0) {
      if (channels) *channels = n;
      return int64_t(pos + 1);
    }
    std::string name;
    if (!ReadName(value, pos, &name) || value.size() - pos < 16) return -1;
    pos += 16;
  }
}

// The bytes OpenEXR reads for a value of `type` at value[0..]: for the
// types that read a fixed size or parse their content (chlist, preview,
// stringvector, floatvector) instead of reading `value.size()` bytes, what
// they would consume; -1 when the content runs past the value. Other types
// (string, opaque ones) read exactly the size.
int64_t ValueBytesRead(const std::string& type, std::span<const uint8_t> value) {
  if (const size_t fixed = FixedValueSize(type); fixed > 0) return int64_t(fixed);
  if (type == "chlist") return WalkChannels(value, nullptr);
  if (type == "preview") {
    // Width and height, then 4 bytes per pixel, allocated before reading.
    if (value.size() < 8) return -1;
    const uint64_t pixels = uint64_t(Le32(value, 0)) * uint64_t(Le32(value, 4));
    if (pixels > (value.size() - 8) / 4) return -1;
    return int64_t(8 + 4 * pixels);
  }
  if (type == "stringvector") {
    // Strings, each after its length, until the size is used up; each
    // string is allocated at its claimed length first.
    size_t pos = 0;
    while (pos < value.size()) {
      if (value.size() - pos < 4) return -1;
      const int32_t length = int32_t(Le32(value, pos));
      pos += 4;
      if (length < 0 || size_t(length) > value.size() - pos) return -1;
      pos += size_t(length);
    }
    return int64_t(pos);
  }
  // floatvector reads whole floats only.
  if (type == "floatvector") return int64_t(value.size() / 4 * 4);
  return int64_t(value.size());
}

// The buffers OpenEXR sizes from `name`'s value when it opens the file.
absl::Status CheckSizing(const std::string& name, const std::string& type,
                         std::span<const uint8_t> value, const ExrHeaderLimits& limits,
                         const std::string& field) {
  if (type == "box2i" && name == "dataWindow") {
    const int64_t width = int64_t(int32_t(Le32(value, 8))) - int64_t(int32_t(Le32(value, 0))) + 1;
    const int64_t height = int64_t(int32_t(Le32(value, 12))) - int64_t(int32_t(Le32(value, 4))) + 1;
    if (width < 1 || height < 1) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": corrupt exr image: dataWindow is ",
                                                     width, "x", height, " pixels"));
    }
    if (width > limits.max_dimension || height > limits.max_dimension) {
      return absl::ResourceExhaustedError(absl::StrCat(field, ": ", width, "x", height,
                                                       " pixels exceed the limit of ",
                                                       limits.max_dimension, " per side"));
    }
  }
  if (type == "tiledesc") {
    const uint32_t x = Le32(value, 0), y = Le32(value, 4);
    if (x < 1 || y < 1 || x > limits.max_dimension || y > limits.max_dimension) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": corrupt exr image: tiles of ", x,
                                                     "x", y, " pixels (at most ",
                                                     limits.max_dimension, " per side)"));
    }
  }
  if (type == "chlist") {
    int channels = 0;
    WalkChannels(value, &channels);
    if (channels > limits.max_channels) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": ", channels, " channels; at most ",
                                                     limits.max_channels,
                                                     " are accepted (RGBA is used)"));
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status CheckExrHeader(std::span<const uint8_t> bytes, const std::string& field,
                            const ExrHeaderLimits& limits) {
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
      const int32_t size = int32_t(Le32(bytes, pos));
      pos += 4;
      if (size < 0 || uint64_t(size) > bytes.size() - pos) {
        return corrupt(absl::StrCat("attribute '", name, "' claims ", size, " bytes, ",
                                    bytes.size() - pos, " remain"));
      }
      // A value read with another length than its size field leaves
      // OpenEXR reading the next attribute from the wrong place (found by
      // the fuzzer: a chlist ending early, then a 1.9 GB "attribute").
      const int64_t read = ValueBytesRead(type, bytes.subspan(pos, size_t(size)));
      if (read != int64_t(size)) {
        return corrupt(absl::StrCat("attribute '", name, "' of type ", type, " holds ",
                                    read < 0 ? std::string("more") : absl::StrCat(read),
                                    " bytes of value in a size of ", size));
      }
      GS_RETURN_IF_ERROR(CheckSizing(name, type, bytes.subspan(pos, size_t(size)), limits, field));
      pos += size_t(size);
    }
    if (!multi_part) return absl::OkStatus();
  }
}

}  // namespace gistream
