#include "encode/encode_checks.h"

#include <cstdint>

namespace gistream {

absl::Status CheckImageArgs(size_t elements, int width, int height, int channels,
                            absl::string_view what) {
  if (width <= 0 || height <= 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(what, ": size ", width, "x", height, " must be positive"));
  }
  uint64_t expected = 0;
  if (__builtin_mul_overflow(static_cast<uint64_t>(width), static_cast<uint64_t>(height),
                             &expected) ||
      __builtin_mul_overflow(expected, static_cast<uint64_t>(channels), &expected) ||
      expected != elements) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": got ", elements, " values, expected ",
                                                   width, "x", height, "x", channels));
  }
  return absl::OkStatus();
}

}  // namespace gistream
