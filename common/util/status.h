// Status helpers shared by the whole server. Errors are values: absl::Status
// with a message that names the offending field and its value.
#pragma once

#include <absl/status/status.h>
#include <absl/status/statusor.h>
#include <absl/strings/str_cat.h>

#define GS_RETURN_IF_ERROR(expr)                \
  do {                                          \
    if (absl::Status _st = (expr); !_st.ok()) { \
      return _st;                               \
    }                                           \
  } while (0)

#define GS_CONCAT_INNER(a, b) a##b
#define GS_CONCAT(a, b) GS_CONCAT_INNER(a, b)
#define GS_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                             \
  if (!tmp.ok()) return tmp.status();            \
  lhs = std::move(tmp).value()
#define GS_ASSIGN_OR_RETURN(lhs, expr) \
  GS_ASSIGN_OR_RETURN_IMPL(GS_CONCAT(_statusor_, __LINE__), lhs, expr)

// Invariant checks for our own code (not for bad input, which gets a Status).
#define GS_CHECK(cond)                                               \
  do {                                                               \
    if (!(cond)) ::gistream::CheckFailed(__FILE__, __LINE__, #cond); \
  } while (0)

namespace gistream {
[[noreturn]] void CheckFailed(const char* file, int line, const char* cond);
}  // namespace gistream
