// Per-stage statistics and the table `stream` and `script` print
// (client/stats_table.h).
#include <chrono>
#include <string>

#include <gtest/gtest.h>

#include "stats_table.h"

namespace gistream::client {
namespace stats_table_test {

using Clock = StatsCollector::Clock;

v1::Frame MakeFrame(double total_ms, uint32_t dropped = 0) {
  v1::Frame frame;
  frame.set_total_ms(total_ms);
  frame.set_dropped_frames(dropped);
  return frame;
}

void AddTiming(v1::Frame& frame, const std::string& name, double cpu, double gpu,
               bool skipped = false, bool cpu_stage = false) {
  v1::StageTiming* timing = frame.add_timings();
  timing->set_name(name);
  timing->set_cpu_ms(cpu);
  timing->set_gpu_ms(gpu);
  timing->set_skipped(skipped);
  timing->set_cpu_stage(cpu_stage);
}

TEST(Percentile, HandExamples) {
  EXPECT_FALSE(Percentile({}, 50).has_value());
  EXPECT_DOUBLE_EQ(*Percentile({7}, 50), 7.0);
  EXPECT_DOUBLE_EQ(*Percentile({7}, 95), 7.0);
  EXPECT_DOUBLE_EQ(*Percentile({3, 1, 2}, 50), 2.0);     // odd count: the middle
  EXPECT_DOUBLE_EQ(*Percentile({4, 1, 3, 2}, 50), 2.5);  // even count: mean of the middle two
  // 1..20: rank 0.95 * 19 = 18.05 -> 19 + 0.05 * (20 - 19).
  std::vector<double> values;
  for (int i = 20; i >= 1; --i) values.push_back(i);
  EXPECT_NEAR(*Percentile(values, 95), 19.05, 1e-12);
  EXPECT_DOUBLE_EQ(*Percentile(values, 0), 1.0);
  EXPECT_DOUBLE_EQ(*Percentile(values, 100), 20.0);
}

TEST(StatsCollector, SummarizesRunsSkipsAndCpuStages) {
  StatsCollector stats;
  const Clock::time_point start = Clock::now();
  for (int i = 0; i < 4; ++i) {
    v1::Frame frame = MakeFrame(10.0 + i, i == 3 ? 2 : 0);
    AddTiming(frame, "apply_updates", 0.1 * (i + 1), 0.0);
    // Solver stage runs on the first frame only (camera-only changes later).
    AddTiming(frame, "shadow_maps", 1.0, 2.0 + i, /*skipped=*/i > 0);
    AddTiming(frame, "trace", 5.0 + i, 0.0, false, /*cpu_stage=*/true);
    (*frame.mutable_stats())["vpls"] = 256 + i;
    stats.Add(frame, start + std::chrono::milliseconds(100 * i));
  }
  const StatsSummary summary = stats.Summarize();
  EXPECT_EQ(summary.frames, 4);
  ASSERT_EQ(summary.stages.size(), 3u);

  const StageSummary& apply = summary.stages[0];
  EXPECT_EQ(apply.name, "apply_updates");
  EXPECT_EQ(apply.runs, 4);
  EXPECT_EQ(apply.skipped, 0);
  EXPECT_NEAR(*apply.cpu_median, 0.25, 1e-12);
  EXPECT_FALSE(apply.cpu_stage);
  EXPECT_DOUBLE_EQ(*apply.gpu_median, 0.0);

  const StageSummary& shadows = summary.stages[1];
  EXPECT_EQ(shadows.runs, 1);
  EXPECT_EQ(shadows.skipped, 3);
  EXPECT_DOUBLE_EQ(*shadows.gpu_median, 2.0);  // skipped frames do not count
  EXPECT_DOUBLE_EQ(*shadows.gpu_p95, 2.0);

  const StageSummary& trace = summary.stages[2];
  EXPECT_TRUE(trace.cpu_stage);
  EXPECT_DOUBLE_EQ(*trace.cpu_median, 6.5);
  EXPECT_FALSE(trace.gpu_median.has_value());

  EXPECT_DOUBLE_EQ(*summary.total_median, 11.5);
  EXPECT_NEAR(*summary.total_p95, 12.85, 1e-12);
  EXPECT_NEAR(*summary.fps, 10.0, 1e-9);  // 3 intervals in 0.3 s
  EXPECT_EQ(summary.dropped, 2u);
  EXPECT_FALSE(summary.round_trip_median.has_value());
  EXPECT_DOUBLE_EQ(summary.last_stats.at("vpls"), 259.0);
}

TEST(StatsCollector, StageThatNeverRanPrintsDashes) {
  StatsCollector stats;
  v1::Frame frame = MakeFrame(5.0);
  AddTiming(frame, "environment", 0, 0, /*skipped=*/true);
  stats.Add(frame, Clock::now(), 7.5);
  const StatsSummary summary = stats.Summarize();
  ASSERT_EQ(summary.stages.size(), 1u);
  EXPECT_EQ(summary.stages[0].runs, 0);
  EXPECT_FALSE(summary.stages[0].cpu_median.has_value());
  EXPECT_FALSE(summary.fps.has_value());  // one frame: no interval
  EXPECT_DOUBLE_EQ(*summary.round_trip_median, 7.5);
}

TEST(FormatStatsTable, Layout) {
  StatsSummary summary;
  summary.frames = 2;
  StageSummary gbuffer{.name = "gbuffer",
                       .runs = 2,
                       .skipped = 0,
                       .cpu_stage = false,
                       .cpu_median = 0.05,
                       .cpu_p95 = 0.06,
                       .gpu_median = 1.25,
                       .gpu_p95 = 1.5};
  StageSummary trace{.name = "trace",
                     .runs = 1,
                     .skipped = 1,
                     .cpu_stage = true,
                     .cpu_median = 12.0,
                     .cpu_p95 = 12.0,
                     .gpu_median = {},
                     .gpu_p95 = {}};
  summary.stages = {gbuffer, trace};
  summary.total_median = 14.0;
  summary.total_p95 = 15.5;
  summary.fps = 29.96;
  summary.dropped = 1;
  summary.last_stats = {{"iterations", 3}, {"memory_mb", 1.5}};
  EXPECT_EQ(FormatStatsTable(summary),
            "per-stage timings over 2 frames (ms):\n"
            "stage   | runs | skipped | CPU median | CPU p95 | GPU median | GPU p95\n"
            "--------+------+---------+------------+---------+------------+--------\n"
            "gbuffer |    2 |       0 |       0.05 |    0.06 |       1.25 |    1.50\n"
            "trace   |    1 |       1 |      12.00 |   12.00 |          - |       -\n"
            "frame total (server): median 14.00 ms, p95 15.50 ms\n"
            "achieved: 30.0 fps, dropped frames: 1\n"
            "solver stats (last frame): iterations=3 memory_mb=1.5\n");
}

}  // namespace stats_table_test
}  // namespace gistream::client
