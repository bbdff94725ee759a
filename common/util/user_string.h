// User-supplied strings (names, ids, paths, parameter values) echoed in
// error messages: cut to kMaxEchoBytes so a 100 KB name does not come back
// whole in every error (and in every log line), marked with "…".
#pragma once

#include <absl/strings/string_view.h>

#include <string>

namespace gistream {

// 64 bytes keep any real name, path or id readable; more is an attack or
// an accident, and the start is enough to recognise it.
inline constexpr size_t kMaxEchoBytes = 64;

inline std::string Echo(absl::string_view s) {
  if (s.size() <= kMaxEchoBytes) return std::string(s);
  size_t cut = kMaxEchoBytes;
  // Do not split a UTF-8 sequence: back up over continuation bytes.
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
  return absl::StrCat(s.substr(0, cut), "\u2026 (", s.size(), " bytes)");
}

}  // namespace gistream
