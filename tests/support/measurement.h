// A test's measured figures (errors, means, residuals) are recorded as
// gtest properties rather than printed: they appear in the test report
// (`--gtest_output=xml:FILE`, or ctest's `--output-junit`), keyed by name,
// next to the assertion that judged them.
#pragma once

#include <string>
#include <string_view>

#include <absl/strings/str_format.h>
#include <gtest/gtest.h>

namespace gistream::testing {

// Records `value` under `key` (letters, digits, '_', '.'; gtest reserves
// name, status, time, classname, type_param and value_param).
inline void RecordMeasurement(std::string_view key, double value) {
  ::testing::Test::RecordProperty(std::string(key), absl::StrFormat("%.6g", value));
}

}  // namespace gistream::testing
