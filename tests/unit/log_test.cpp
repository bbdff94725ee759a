// The log line format: ISO-8601 UTC timestamp with milliseconds, the level
// padded to five columns, then session= and scene= where given, then the
// message; and the thread's ScopedLogContext as the default.
#include <regex>

#include <gtest/gtest.h>

#include "util/log.h"

namespace gistream {
namespace log_test {

using std::chrono::milliseconds;
using std::chrono::system_clock;

// 2026-12-01T15:04:05.123Z
system_clock::time_point Example() {
  return system_clock::time_point(milliseconds(1796137445123LL));
}

TEST(LogFormat, TimestampLevelIdsMessage) {
  EXPECT_EQ(FormatLogLine(Example(), LogLevel::kInfo, {"session-3", "cornell_box-1"},
                          "opened (direct, 128x128)"),
            "2026-12-01T15:04:05.123Z info  session=session-3 scene=cornell_box-1 opened (direct, "
            "128x128)");
}

TEST(LogFormat, IdsAreLeftOutWhenEmpty) {
  EXPECT_EQ(FormatLogLine(Example(), LogLevel::kWarning, {}, "x"),
            "2026-12-01T15:04:05.123Z warn  x");
  EXPECT_EQ(FormatLogLine(Example(), LogLevel::kError, {"", "furnace-2"}, "gone"),
            "2026-12-01T15:04:05.123Z error scene=furnace-2 gone");
  EXPECT_EQ(FormatLogLine(Example(), LogLevel::kDebug, {"session-9", ""}, "y"),
            "2026-12-01T15:04:05.123Z debug session=session-9 y");
}

TEST(LogFormat, MillisecondsArePaddedAndTheClockIsUtc) {
  const auto t = system_clock::time_point(milliseconds(5));  // 1970-01-01 00:00:00.005 UTC
  EXPECT_EQ(FormatLogLine(t, LogLevel::kInfo, {}, "m"), "1970-01-01T00:00:00.005Z info  m");
}

TEST(LogFormat, NowHasTheIsoShape) {
  const std::string line = FormatLogLine(system_clock::now(), LogLevel::kInfo, {"s", "c"}, "m");
  EXPECT_TRUE(std::regex_match(
      line, std::regex(R"(\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}\.\d{3}Z info  session=s scene=c m)")))
      << line;
}

TEST(LogFormat, ScopedContextIsTheThreadsDefault) {
  // Log() writes to stderr; capture it.
  ::testing::internal::CaptureStderr();
  {
    const ScopedLogContext outer({"session-1", "box-1"});
    Log(LogLevel::kInfo, "inside");
    {
      const ScopedLogContext inner({"session-2", "box-2"});
      Log(LogLevel::kInfo, "nested");
    }
    Log(LogLevel::kInfo, {"session-5", ""}, "explicit ids win");
  }
  Log(LogLevel::kInfo, "outside");
  const std::string out = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(out.find(" info  session=session-1 scene=box-1 inside\n"), std::string::npos) << out;
  EXPECT_NE(out.find(" info  session=session-2 scene=box-2 nested\n"), std::string::npos) << out;
  EXPECT_NE(out.find(" info  session=session-5 explicit ids win\n"), std::string::npos) << out;
  EXPECT_NE(out.find("Z info  outside\n"), std::string::npos) << out;
}

}  // namespace log_test
}  // namespace gistream
