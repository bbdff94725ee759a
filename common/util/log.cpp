#include "util/log.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <mutex>
#include <set>

#include "util/status.h"

namespace gistream {
namespace {
std::mutex g_mutex;
std::atomic<int> g_level{static_cast<int>(LogLevel::kInfo)};
thread_local const LogContext* t_context = nullptr;

// Padded to five columns so messages line up.
const char* Name(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug: return "debug";
    case LogLevel::kInfo: return "info ";
    case LogLevel::kWarning: return "warn ";
    case LogLevel::kError: return "error";
  }
  return "?    ";
}
}  // namespace

void SetLogLevel(LogLevel level) { g_level = static_cast<int>(level); }

bool LogEnabled(LogLevel level) { return static_cast<int>(level) >= g_level.load(); }

std::string FormatLogLine(std::chrono::system_clock::time_point time, LogLevel level,
                          const LogContext& context, std::string_view message) {
  using namespace std::chrono;
  const auto since_epoch = time.time_since_epoch();
  const time_t seconds = duration_cast<std::chrono::seconds>(since_epoch).count();
  const auto millis = duration_cast<milliseconds>(since_epoch).count() % 1000;
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char stamp[80];
  std::snprintf(stamp, sizeof(stamp), "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", utc.tm_year + 1900,
                utc.tm_mon + 1, utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec,
                static_cast<int>(millis < 0 ? millis + 1000 : millis));
  std::string line = absl::StrCat(stamp, " ", Name(level), " ");
  if (!context.session.empty()) {
    absl::StrAppend(
        &line, "session=", absl::string_view(context.session.data(), context.session.size()), " ");
  }
  if (!context.scene.empty()) {
    absl::StrAppend(&line, "scene=", absl::string_view(context.scene.data(), context.scene.size()),
                    " ");
  }
  line.append(message);
  return line;
}

void Log(LogLevel level, const LogContext& context, std::string_view message) {
  if (!LogEnabled(level)) return;
  LogContext effective = context;
  if (t_context != nullptr && effective.session.empty() && effective.scene.empty()) {
    effective = *t_context;
  }
  const std::string line =
      FormatLogLine(std::chrono::system_clock::now(), level, effective, message);
  std::lock_guard lock(g_mutex);
  std::fprintf(stderr, "%s\n", line.c_str());
}

void Log(LogLevel level, std::string_view message) { Log(level, LogContext{}, message); }

void LogOnce(LogLevel level, std::string_view key, std::string_view message) {
  static std::set<std::string, std::less<>> seen;
  {
    std::lock_guard lock(g_mutex);
    if (!seen.emplace(key).second) return;
  }
  Log(level, message);
}

ScopedLogContext::ScopedLogContext(const LogContext& context)
    : context_(context), previous_(t_context) {
  t_context = &context_;
}

ScopedLogContext::~ScopedLogContext() { t_context = previous_; }

void CheckFailed(const char* file, int line, const char* cond) {
  std::fprintf(stderr, "CHECK failed at %s:%d: %s\n", file, line, cond);
  std::abort();
}

}  // namespace gistream
