// The render thread's busy share (service/busy_meter.h), on a synthetic
// clock: what admission by GPU time and gistream_render_busy_ratio read.
#include "engine/busy_meter.h"

#include <gtest/gtest.h>

namespace gistream {
namespace busy_meter_test {

using namespace std::chrono_literals;
using Clock = BusyMeter::Clock;

TEST(BusyMeter, RatioIsTheBusyShareOfTheWindow) {
  BusyMeter meter(1s);
  const Clock::time_point t0 = Clock::now();
  EXPECT_EQ(meter.Ratio(t0), 0.0);  // nothing measured yet
  // 10 ms busy every 40 ms for 2 s: a quarter.
  for (int i = 0; i < 50; ++i) {
    const Clock::time_point start = t0 + i * 40ms;
    meter.AddBusy(start, start + 10ms);
  }
  EXPECT_NEAR(meter.Ratio(t0 + 2s), 0.25, 0.011);
  // Idle afterwards: the share falls as the window moves past the work.
  EXPECT_NEAR(meter.Ratio(t0 + 2500ms), 0.125, 0.011);
  EXPECT_EQ(meter.Ratio(t0 + 3100ms), 0.0);
}

TEST(BusyMeter, BeforeAWholeWindowTheShareIsOfTheTimeSoFar) {
  BusyMeter meter(5s);
  const Clock::time_point t0 = Clock::now();
  meter.AddBusy(t0, t0 + 100ms);
  EXPECT_NEAR(meter.Ratio(t0 + 200ms), 0.5, 1e-9);
  // An interval that straddles the window's start counts only inside it.
  BusyMeter straddle(1s);
  straddle.AddBusy(t0, t0 + 1500ms);
  EXPECT_NEAR(straddle.Ratio(t0 + 2s), 0.5, 1e-9);
}

TEST(BusyMeter, AlwaysBusyIsOneNeverMore) {
  BusyMeter meter(1s);
  const Clock::time_point t0 = Clock::now();
  meter.AddBusy(t0, t0 + 3s);
  meter.AddBusy(t0 + 1s, t0 + 2s);  // overlapping reports do not pass 1
  EXPECT_EQ(meter.Ratio(t0 + 2s), 1.0);
  meter.AddBusy(t0 + 2s, t0 + 1s);  // an empty interval is ignored
  EXPECT_EQ(meter.Ratio(t0 + 2s), 1.0);
}

}  // namespace busy_meter_test
}  // namespace gistream
