// gistream bench's arithmetic on synthetic clocks: update-to-frame latency
// matching, frame intervals and gaps, percentiles, Jain's index, the step
// aggregate, and the workloads derived from a scene.
#include <chrono>
#include <cmath>

#include <gtest/gtest.h>

#include "bench_stats.h"
#include "bench_workload.h"
#include "plot.h"

namespace gistream::client {
namespace bench_stats_test {

using std::chrono::milliseconds;

const BenchClock::time_point t0{};
BenchClock::time_point At(int ms) { return t0 + milliseconds(ms); }

TEST(LatencyTracker, AFrameAnswersEveryUpdateUpToItsSeq) {
  LatencyTracker tracker;
  tracker.OnSend(1, At(0));
  tracker.OnSend(2, At(10));
  tracker.OnSend(3, At(20));
  // A frame that applied nothing new answers nothing.
  EXPECT_EQ(tracker.OnFrame(0, At(25)), 0);
  // The frame that applied up to seq 2 answers 1 and 2, at their own ages.
  EXPECT_EQ(tracker.OnFrame(2, At(40)), 2);
  ASSERT_EQ(tracker.latencies_ms().size(), 2u);
  EXPECT_DOUBLE_EQ(tracker.latencies_ms()[0], 40.0);
  EXPECT_DOUBLE_EQ(tracker.latencies_ms()[1], 30.0);
  EXPECT_EQ(tracker.unanswered(), 1u);
  // Later frames that repeat seq 2 answer nothing more; seq 3 waits.
  EXPECT_EQ(tracker.OnFrame(2, At(50)), 0);
  EXPECT_DOUBLE_EQ(*tracker.OldestPendingAgeMs(At(70)), 50.0);
  EXPECT_EQ(tracker.OnFrame(7, At(90)), 1);
  EXPECT_DOUBLE_EQ(tracker.latencies_ms()[2], 70.0);
  EXPECT_EQ(tracker.unanswered(), 0u);
  EXPECT_FALSE(tracker.OldestPendingAgeMs(At(100)).has_value());
}

TEST(LatencyTracker, UnmeasuredUpdatesAreMatchedButNotCounted) {
  LatencyTracker tracker;
  tracker.OnSend(1, At(0), /*measured=*/false);  // warm-up
  tracker.OnSend(2, At(5), /*measured=*/true);
  EXPECT_EQ(tracker.unanswered(), 1u);
  EXPECT_EQ(tracker.OnFrame(2, At(25)), 2);
  ASSERT_EQ(tracker.latencies_ms().size(), 1u);
  EXPECT_DOUBLE_EQ(tracker.latencies_ms()[0], 20.0);
}

TEST(LatencyTracker, ARejectedUpdateLeavesThePendingSet) {
  LatencyTracker tracker;
  tracker.OnSend(1, At(0));
  tracker.OnSend(2, At(1));
  tracker.OnRejected(1);
  EXPECT_EQ(tracker.rejected(), 1u);
  EXPECT_EQ(tracker.unanswered(), 1u);
  EXPECT_EQ(tracker.OnFrame(2, At(11)), 1);
  EXPECT_DOUBLE_EQ(tracker.latencies_ms()[0], 10.0);
}

TEST(FrameIntervals, IntervalsInsideTheWindowAndTheOpenGapsAtItsEnds) {
  FrameIntervals intervals(At(100), At(1100));
  EXPECT_FALSE(intervals.Add(At(90)));  // warm-up
  EXPECT_TRUE(intervals.Add(At(150)));
  EXPECT_TRUE(intervals.Add(At(183)));
  EXPECT_TRUE(intervals.Add(At(700)));
  EXPECT_FALSE(intervals.Add(At(1100)));  // the window is half open
  SessionMeasurement m;
  m.window_s = 1.0;
  intervals.Finish(m);
  EXPECT_EQ(m.frames, 3);
  ASSERT_EQ(m.intervals_ms.size(), 2u);
  EXPECT_DOUBLE_EQ(m.intervals_ms[0], 33.0);
  EXPECT_DOUBLE_EQ(m.intervals_ms[1], 517.0);
  // The stream stopped at 700: the gap to the window's end is the longest.
  EXPECT_DOUBLE_EQ(m.max_gap_ms, 517.0);
  EXPECT_DOUBLE_EQ(m.fps(), 3.0);
}

TEST(FrameIntervals, NoFrameAtAllIsAGapOfTheWholeWindow) {
  FrameIntervals intervals(At(0), At(2000));
  SessionMeasurement m;
  intervals.Finish(m);
  EXPECT_EQ(m.frames, 0);
  EXPECT_DOUBLE_EQ(m.max_gap_ms, 2000.0);
}

TEST(JainFairness, EqualSharesGiveOneAndOneHogGivesOneOverN) {
  EXPECT_DOUBLE_EQ(JainFairness({30, 30, 30, 30}), 1.0);
  EXPECT_DOUBLE_EQ(JainFairness({40, 0, 0, 0}), 0.25);
  // (10 + 20)^2 / (2 (100 + 400)) = 0.9
  EXPECT_DOUBLE_EQ(JainFairness({10, 20}), 0.9);
  EXPECT_DOUBLE_EQ(JainFairness({}), 1.0);
}

TEST(Summarize, PercentilesInterpolateBetweenClosestRanks) {
  const Quantiles q = Summarize({1, 2, 3, 4, 5, 6, 7, 8, 9, 10});
  EXPECT_DOUBLE_EQ(*q.p50, 5.5);
  EXPECT_DOUBLE_EQ(*q.p95, 9.55);
  EXPECT_DOUBLE_EQ(*q.p99, 9.91);
  EXPECT_DOUBLE_EQ(*q.max, 10.0);
  EXPECT_FALSE(Summarize({}).p50.has_value());
}

TEST(AggregateStep, PoolsSessionsAndKeepsTheLongestGap) {
  SessionMeasurement a, b;
  a.window_s = b.window_s = 2.0;
  a.frames = 60;
  b.frames = 20;
  a.intervals_ms = {30, 35, 40};
  b.intervals_ms = {100, 90};
  a.max_gap_ms = 40;
  b.max_gap_ms = 800;  // b's stream stalled at the end
  a.latencies_ms = {10, 20};
  b.latencies_ms = {50};
  a.updates_sent = 3;
  a.updates_unanswered = 1;
  b.updates_sent = 1;
  a.bytes = 3000;
  b.bytes = 1000;
  b.dropped_frames = 2;
  b.error = "UNAVAILABLE: gone";
  a.settle_ms = 120.0;  // b never settled
  const StepResult step = AggregateStep({a, b}, StatsSummary{}, 2.0);
  EXPECT_EQ(step.sessions, 2);
  EXPECT_DOUBLE_EQ(step.fps_total, 40.0);
  EXPECT_DOUBLE_EQ(step.fps_mean, 20.0);
  EXPECT_DOUBLE_EQ(step.fps_min, 10.0);
  EXPECT_DOUBLE_EQ(step.jain, JainFairness({30, 10}));
  EXPECT_DOUBLE_EQ(*step.latency_ms.p50, 20.0);
  EXPECT_DOUBLE_EQ(*step.latency_ms.max, 50.0);
  EXPECT_DOUBLE_EQ(*step.interval_ms.max, 800.0);
  EXPECT_DOUBLE_EQ(*step.interval_ms.p50, 40.0);
  EXPECT_EQ(step.updates_sent, 4u);
  EXPECT_EQ(step.updates_answered, 3u);
  EXPECT_EQ(step.updates_unanswered, 1u);
  EXPECT_EQ(step.dropped, 2u);
  EXPECT_EQ(step.failed_sessions, 1);
  EXPECT_EQ(step.unsettled, 1);
  EXPECT_DOUBLE_EQ(*step.settle_ms.max, 120.0);
  EXPECT_DOUBLE_EQ(step.bytes_per_s, 2000.0);
  EXPECT_EQ(step.all_latencies_ms, (std::vector<double>{10, 20, 50}));
}

v1::LoadSceneResponse BoxScene(bool with_light) {
  v1::LoadSceneResponse scene;
  scene.mutable_bounds()->mutable_min()->set_x(0);
  scene.mutable_bounds()->mutable_max()->set_x(1);
  scene.mutable_bounds()->mutable_max()->set_y(1);
  scene.mutable_bounds()->mutable_max()->set_z(1);
  auto* floor = scene.add_nodes();
  floor->set_id(0);
  floor->set_name("floor");
  floor->set_mesh(0);
  auto* block = scene.add_nodes();
  block->set_id(5);
  block->set_name("tall_block");
  block->set_mesh(1);
  block->mutable_translation()->set_x(0.3f);
  auto* camera = scene.add_cameras();
  camera->mutable_position()->set_x(0.5f);
  camera->mutable_position()->set_y(0.5f);
  camera->mutable_position()->set_z(2.5f);
  auto* lamp = scene.add_materials();
  lamp->set_id(3);
  lamp->set_name("light");
  lamp->mutable_emissive()->set_x(17);
  lamp->mutable_emissive()->set_y(8.5f);
  if (with_light) {
    auto* light = scene.add_lights();
    light->set_id(0);
    light->set_type(v1::LIGHT_TYPE_POINT);
    light->set_intensity(10);
    light->mutable_position()->set_y(0.9f);
  }
  return scene;
}

TEST(Workload, OrbitSwingsAroundTheSceneCentreAtTheCameraDistance) {
  auto w = Workload::Create(*ParseWorkload("orbit"), BoxScene(false));
  ASSERT_TRUE(w.ok()) << w.status();
  for (uint64_t tick : {0u, 7u, 15u, 31u}) {
    const auto updates = w->UpdatesForTick(tick);
    ASSERT_EQ(updates.size(), 1u);
    const v1::LookAt& look = updates[0].camera().look_at();
    const float dx = look.eye().x() - 0.5f, dz = look.eye().z() - 0.5f;
    EXPECT_NEAR(std::sqrt(dx * dx + dz * dz), 2.0f, 1e-4f) << tick;
    EXPECT_FLOAT_EQ(look.eye().y(), 0.5f);
    EXPECT_FLOAT_EQ(look.target().x(), 0.5f);
  }
  // Tick 0 starts at the camera; tick 15 is a quarter period: +15 degrees.
  EXPECT_NEAR(w->UpdatesForTick(0)[0].camera().look_at().eye().z(), 2.5f, 1e-4f);
  const v1::Vec3 eye = w->UpdatesForTick(15)[0].camera().look_at().eye();
  EXPECT_NEAR(std::atan2(eye.z() - 0.5f, eye.x() - 0.5f) * 180.0 / M_PI, 90.0 + 15.0, 1e-3);
}

TEST(Workload, LightUsesThePunctualLightElseTheEmitter) {
  auto punctual = Workload::Create(*ParseWorkload("light"), BoxScene(true));
  ASSERT_TRUE(punctual.ok()) << punctual.status();
  const v1::Update u = punctual->UpdatesForTick(10)[0];  // a quarter period: × 1.3
  ASSERT_TRUE(u.has_light());
  EXPECT_NEAR(u.light().intensity(), 13.0f, 1e-4f);
  EXPECT_TRUE(u.light().has_position());

  auto emitter = Workload::Create(*ParseWorkload("light"), BoxScene(false));
  ASSERT_TRUE(emitter.ok()) << emitter.status();
  const v1::Update m = emitter->UpdatesForTick(10)[0];
  ASSERT_TRUE(m.has_material());
  EXPECT_EQ(m.material().material(), 3u);
  // factor × strength restores the emission, scaled by 1.3.
  EXPECT_FLOAT_EQ(m.material().emissive().x(), 1.0f);
  EXPECT_NEAR(m.material().emissive().x() * m.material().emissive_strength(), 17.0f * 1.3f, 1e-3f);
  EXPECT_NEAR(m.material().emissive().y() * m.material().emissive_strength(), 8.5f * 1.3f, 1e-3f);
}

TEST(Workload, ObjectMovesTheBlockAndMixedTakesTurns) {
  auto object = Workload::Create(*ParseWorkload("object"), BoxScene(false));
  ASSERT_TRUE(object.ok()) << object.status();
  const v1::Update u = object->UpdatesForTick(10)[0];
  ASSERT_TRUE(u.has_node_transform());
  EXPECT_EQ(u.node_transform().node(), 5u);
  // 3 % of the diagonal (sqrt 3) at the peak of the swing.
  EXPECT_NEAR(u.node_transform().translation().x(), 0.3f + 0.03f * std::sqrt(3.0f), 1e-4f);
  EXPECT_FLOAT_EQ(u.node_transform().scale().y(), 1.0f);
  EXPECT_FLOAT_EQ(u.node_transform().rotation().w(), 1.0f);

  auto mixed = Workload::Create(*ParseWorkload("mixed"), BoxScene(false));
  ASSERT_TRUE(mixed.ok()) << mixed.status();
  EXPECT_TRUE(mixed->UpdatesForTick(0)[0].has_camera());
  EXPECT_TRUE(mixed->UpdatesForTick(1)[0].has_material());
  EXPECT_TRUE(mixed->UpdatesForTick(2)[0].has_node_transform());
}

TEST(Workload, ErrorsNameWhatIsMissing) {
  EXPECT_FALSE(ParseWorkload("spin").ok());
  v1::LoadSceneResponse empty;
  const auto light = Workload::Create(*ParseWorkload("light"), empty);
  EXPECT_EQ(light.status().code(), absl::StatusCode::kFailedPrecondition);
  WorkloadSpec spec = *ParseWorkload("object");
  spec.node = "teapot";
  const auto node = Workload::Create(spec, BoxScene(false));
  EXPECT_EQ(node.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(node.status().message().find("teapot"), std::string::npos);
}

TEST(Plot, LinearAxesPlaceValuesProportionally) {
  const std::vector<PlotSeries> series = {{"cdf", {{1.0, 0.0}, {10.0, 0.5}, {100.0, 1.0}}}};
  PlotStyle style{.x_title = "ms",
                  .y_title = "fraction",
                  .x_scale = AxisScale::kLog,
                  .y_scale = AxisScale::kLinear,
                  .markers = false};
  LogAxes axes;
  ASSERT_TRUE(ComputeAxes(series, style, 400, 300, axes));
  EXPECT_FALSE(axes.y_log);
  EXPECT_DOUBLE_EQ(axes.y0, 0.0);
  EXPECT_GE(axes.y1, 1.0);
  // 0.5 lies halfway between 0 and 1 on a linear axis.
  EXPECT_NEAR(axes.Y(0.5), (axes.Y(0.0) + axes.Y(1.0)) / 2.0, 1.0);
  const Raster r = PlotLines(series, style, 400, 300);
  // The curve's midpoint is drawn in the series colour.
  const auto colour = SeriesColor(0);
  EXPECT_EQ(r.at(axes.X(10.0), axes.Y(0.5)), colour);
}

}  // namespace bench_stats_test
}  // namespace gistream::client
