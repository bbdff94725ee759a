// Small helpers shared by the glTF import stages: field names in the
// JSON-pointer-ish form our messages use, and overflow-checked arithmetic.
#pragma once

#include <absl/strings/string_view.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "util/status.h"

namespace gistream::gltf {

// Values we store as float must fit in one.
inline constexpr double kMaxFloat = std::numeric_limits<float>::max();

// "accessors[3]".
inline std::string Item(absl::string_view array, uint64_t index) {
  return absl::StrCat(array, "[", index, "]");
}

// a * b + c, or false on overflow.
inline bool MulAdd(uint64_t a, uint64_t b, uint64_t c, uint64_t* out) {
  uint64_t product = 0;
  return !__builtin_mul_overflow(a, b, &product) && !__builtin_add_overflow(product, c, out);
}

// Checks that `index` names one of `size` entries of `array`.
inline absl::Status CheckIndex(absl::string_view field, int64_t index, size_t size,
                               absl::string_view array) {
  if (index < 0 || static_cast<uint64_t>(index) >= size) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": ", index, " is out of range (", size, " ", array, ")"));
  }
  return absl::OkStatus();
}

// Checks that every value is finite, naming "field[i]".
template <typename Range>
absl::Status CheckFinite(absl::string_view field, const Range& values) {
  size_t i = 0;
  for (double v : values) {
    if (!std::isfinite(v)) {
      return absl::InvalidArgumentError(absl::StrCat(field, "[", i, "]: ", v, " is not finite"));
    }
    ++i;
  }
  return absl::OkStatus();
}

// Checks lo <= v <= hi for every value, naming "field[i]"; NaN fails.
template <typename Range>
absl::Status CheckRange(absl::string_view field, const Range& values, double lo, double hi) {
  size_t i = 0;
  for (double v : values) {
    if (!(v >= lo && v <= hi)) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, "[", i, "]: ", v, " is out of range [", lo, ", ", hi, "]"));
    }
    ++i;
  }
  return absl::OkStatus();
}

// Checks lo <= value <= hi; NaN fails.
inline absl::Status CheckNumber(absl::string_view field, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi)) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": ", value, " is out of range [", lo, ", ", hi, "]"));
  }
  return absl::OkStatus();
}

}  // namespace gistream::gltf
