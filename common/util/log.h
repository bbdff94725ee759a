// Thread-safe logging to stderr, one line per message:
//
//   2026-12-01T15:04:05.123Z info  session=session-3 scene=cornell_box-1 opened (direct, 128x128)
//
// an ISO-8601 UTC timestamp with milliseconds, the level (padded to five
// columns), the session and scene the line concerns where there is one, then
// the message. Ids come from the call (LogContext) or, failing that, from
// the innermost ScopedLogContext on the calling thread (the render thread
// sets one around each frame, so a solver's warning names its session).
// Also a log-once helper for per-frame warnings.
#pragma once

#include <chrono>
#include <string>
#include <string_view>

namespace gistream {

enum class LogLevel { kDebug, kInfo, kWarning, kError };

// What a line concerns; empty fields are left out of the line.
struct LogContext {
  std::string_view session;
  std::string_view scene;
};

void Log(LogLevel level, std::string_view message);
void Log(LogLevel level, const LogContext& context, std::string_view message);
// Logs `message` the first time `key` is seen, then stays quiet.
void LogOnce(LogLevel level, std::string_view key, std::string_view message);
void SetLogLevel(LogLevel level);
bool LogEnabled(LogLevel level);

// The line Log writes (without the newline), for tests.
std::string FormatLogLine(std::chrono::system_clock::time_point time, LogLevel level,
                          const LogContext& context, std::string_view message);

// Sets the calling thread's default LogContext until destroyed (it keeps a
// copy of the views: the strings they view must outlive the scope). Scopes
// nest; the innermost wins.
class ScopedLogContext {
 public:
  explicit ScopedLogContext(const LogContext& context);
  ~ScopedLogContext();
  ScopedLogContext(const ScopedLogContext&) = delete;
  ScopedLogContext& operator=(const ScopedLogContext&) = delete;

 private:
  const LogContext context_;
  const LogContext* previous_;
};

}  // namespace gistream
