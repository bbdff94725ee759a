// FrameRate (the per-session fps in GetServerStatus) on a synthetic clock:
// frames in the last 5 s over 5 s, or over the time since the start when
// that is shorter; old frames fall out of the window.
#include <gtest/gtest.h>

#include "engine/frame_rate.h"

namespace gistream {
namespace frame_rate_test {

using namespace std::chrono_literals;
using Clock = FrameRate::Clock;

TEST(FrameRate, CountsOverTheTimeSinceStartWhileShorterThanTheWindow) {
  const Clock::time_point t0{};
  FrameRate rate(t0);
  EXPECT_EQ(rate.PerSecond(t0), 0.0);  // no time has passed
  for (int i = 1; i <= 10; ++i) rate.Add(t0 + i * 100ms);
  EXPECT_DOUBLE_EQ(rate.PerSecond(t0 + 1s), 10.0);
  EXPECT_DOUBLE_EQ(rate.PerSecond(t0 + 2s), 5.0);  // a stall lowers it
}

TEST(FrameRate, UsesTheLastFiveSeconds) {
  const Clock::time_point t0{};
  FrameRate rate(t0);
  for (int i = 1; i <= 100; ++i) rate.Add(t0 + i * 100ms);  // 10 fps for 10 s
  EXPECT_DOUBLE_EQ(rate.PerSecond(t0 + 10s), 10.0);         // frames in (5 s, 10 s]
  EXPECT_DOUBLE_EQ(rate.PerSecond(t0 + 12500ms), 5.0);      // 25 frames in (7.5 s, 12.5 s]
  EXPECT_EQ(rate.PerSecond(t0 + 20s), 0.0);                 // all fell out
}

}  // namespace frame_rate_test
}  // namespace gistream
