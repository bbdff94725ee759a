// sh_probes' progressive schedule (solvers/sh_probes/probe_schedule.h):
// the order after a change, batches bounded by their work, and when the
// sweeps stop.
#include "solvers/sh_probes/probe_schedule.h"

#include <gtest/gtest.h>

namespace gistream {
namespace sh_probe_schedule_test {

// Eight probes on a line at x = 0..7.
std::vector<glm::vec3> Line() {
  std::vector<glm::vec3> p;
  for (int i = 0; i < 8; ++i) p.emplace_back(float(i), 0.0f, 0.0f);
  return p;
}

std::vector<int> SweepOrder(ProbeSchedule& s) {
  std::vector<int> order;
  while (s.pending() && order.size() < 8) {
    const ProbeSchedule::Batch b = s.Peek();
    order.insert(order.end(), b.probes.begin(), b.probes.end());
    s.Done(b, 1.0, 1.0, 0.01, 10);
  }
  return order;
}

TEST(ProbeSchedule, AffectedProbesFirstThenNearerTheCamera) {
  ProbeSchedule s;
  s.Reset(8);
  EXPECT_FALSE(s.pending());
  const std::vector<int32_t> seen = {0, 0, 0, 0, 0, 100, 0, 100};
  s.Prioritize(seen, Line(), glm::vec3(2.2f, 0.0f, 0.0f));
  EXPECT_TRUE(s.pending());
  // 7 and 5 saw as much of the change: 5 is nearer the eye; then the rest
  // by distance (ties by index).
  EXPECT_EQ(SweepOrder(s), (std::vector<int>{5, 7, 2, 3, 1, 4, 0, 6}));
}

TEST(ProbeSchedule, ProbesThatSeeMoreOfTheChangeComeFirst) {
  ProbeSchedule s;
  s.Reset(8);
  // 1 sees a sliver of the change, 6 most of its sphere, 3 a part: the
  // projections that change most are redone first, whatever the distance.
  const std::vector<int32_t> seen = {0, 1, 0, 5'000, 0, 0, ProbeSchedule::kWholeSphere, 0};
  s.Prioritize(seen, Line(), glm::vec3(0.0f));
  EXPECT_EQ(SweepOrder(s), (std::vector<int>{6, 3, 1, 0, 2, 4, 5, 7}));
}

TEST(ProbeSchedule, BatchesHoldAboutTheBatchUnitsOfWork) {
  ProbeSchedule s;
  s.Reset(40);
  std::vector<glm::vec3> positions(40, glm::vec3(0.0f));
  std::vector<int32_t> seen(40, 0);
  for (int p = 0; p < 8; ++p) {
    seen[size_t(p)] = 1;
    s.NeedRaster(p);
  }
  s.Prioritize(seen, positions, glm::vec3(0.0f));
  const ProbeSchedule::Batch first = s.Peek();
  // A rasterized probe costs raster + direct + bounce units.
  const int per_raster =
      ProbeSchedule::kRasterUnits + ProbeSchedule::kDirectUnits + ProbeSchedule::kBounceUnits;
  EXPECT_EQ(int(first.probes.size()), ProbeSchedule::kBatchUnits / per_raster);
  EXPECT_EQ(first.raster, first.probes);
  EXPECT_EQ(first.direct, first.probes);
  EXPECT_LE(first.units, ProbeSchedule::kBatchUnits);
  // Peek does not take the batch; Done does, and clears its flags.
  EXPECT_EQ(s.Peek().probes, first.probes);
  s.Done(first, 0.0, 1.0, 0.01, 10);
  EXPECT_EQ(s.remaining(), 40 - int(first.probes.size()));
}

TEST(ProbeSchedule, SweepsRepeatUntilOneChangesLessThanTheTolerance) {
  ProbeSchedule s;
  s.Reset(4);
  s.Prioritize(std::vector<int32_t>(4, 0), std::vector<glm::vec3>(4, glm::vec3(0.0f)),
               glm::vec3(0.0f));
  auto sweep = [&](double change_per_probe) {
    while (true) {
      const ProbeSchedule::Batch b = s.Peek();
      const int before = s.sweeps();
      s.Done(b, change_per_probe * double(b.probes.size()), 100.0, 0.01, 5);
      if (s.sweeps() != before) return;
    }
  };
  sweep(1.0);  // 4 / 100 = 0.04 >= 0.01: another sweep
  EXPECT_TRUE(s.pending());
  EXPECT_NEAR(s.last_sweep_change(), 0.04, 1e-12);
  sweep(0.2);  // 0.008 < 0.01: converged
  EXPECT_FALSE(s.pending());
  EXPECT_FALSE(s.cap_reached());
  EXPECT_EQ(s.sweeps(), 2);
}

TEST(ProbeSchedule, NewDirectLightNeedsAnotherSweepAndTheCapStopsIt) {
  ProbeSchedule s;
  s.Reset(2);
  s.NeedDirectAll();  // e.g. the new shadow maps were shown
  EXPECT_TRUE(s.pending());
  const ProbeSchedule::Batch b = s.Peek();
  EXPECT_EQ(b.direct.size(), 2u);
  EXPECT_TRUE(b.raster.empty());
  // Never settling: stops after max_sweeps sweeps, saying so.
  for (int i = 0; i < 3 && s.pending(); ++i) s.Done(s.Peek(), 50.0, 100.0, 0.01, 3);
  EXPECT_FALSE(s.pending());
  EXPECT_TRUE(s.cap_reached());
  EXPECT_EQ(s.sweeps(), 3);
}

}  // namespace sh_probe_schedule_test
}  // namespace gistream
