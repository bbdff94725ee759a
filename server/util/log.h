// Minimal thread-safe logging to stderr, with a log-once helper for
// per-frame warnings.
#pragma once

#include <string_view>

namespace gistream {

enum class LogLevel { kDebug, kInfo, kWarning, kError };

void Log(LogLevel level, std::string_view message);
// Logs `message` the first time `key` is seen, then stays quiet.
void LogOnce(LogLevel level, std::string_view key, std::string_view message);
void SetLogLevel(LogLevel level);

}  // namespace gistream
