// Budgeted, sliced frames through the real engine: a path-traced Render
// and an avg VPL re-map split into many slices give the same image as one
// unsplit frame; their stats and timings cover every slice; a cancelled
// Render stops and leaves the render thread free for the next request.
#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "support/render_helpers.h"

namespace gistream {
namespace {

using testing::BundledCopy;
using testing::FrameStat;
using testing::SharedEngine;

RenderRequest PathtraceRequest(const std::string& scene, int spp, double budget_ms) {
  RenderRequest request = testing::SolverRequest(
      scene, "pathtrace", {{"spp", std::to_string(spp)}, {"seed", "3"}}, 24);
  request.encoding.format = ImageFormat::kExr;
  request.frame_budget_ms = budget_ms;
  return request;
}

TEST(EngineSlicing, ASplitPathtraceFrameEqualsAnUnsplitOne) {
  // Two copies: each accumulates from zero.
  const BundledCopy split_scene("cornell_box.gltf"), whole_scene("cornell_box.gltf");
  // 0.01 ms: every slice traces the minimum of rows, so the 6 passes of
  // 24 rows take dozens of slices; 10 s: one slice does the whole frame.
  auto split = SharedEngine().Render(PathtraceRequest(split_scene.id(), 6, 0.01));
  auto whole = SharedEngine().Render(PathtraceRequest(whole_scene.id(), 6, 10'000.0));
  ASSERT_TRUE(split.ok()) << split.status();
  ASSERT_TRUE(whole.ok()) << whole.status();
  // Each pixel sums the same samples in the same order: bitwise equal
  // (the pixels; the EXR headers carry the time of writing).
  EXPECT_EQ(testing::DecodeExr(*split).rgba, testing::DecodeExr(*whole).rgba);
  EXPECT_EQ(FrameStat(*split, "spp_frame"), 6.0);
  EXPECT_EQ(FrameStat(*split, "spp_total"), 6.0);
  EXPECT_EQ(FrameStat(*split, "frame_complete"), 1.0);
  EXPECT_GT(FrameStat(*split, "slices"), 6.0);  // more slices than passes
  EXPECT_EQ(FrameStat(*whole, "slices"), 1.0);
  EXPECT_EQ(FrameStat(*whole, "rays"), FrameStat(*split, "rays"));
  // The split frame's trace time is the sum over its slices.
  const StageTiming* trace = testing::FrameStage(*split, "trace");
  ASSERT_NE(trace, nullptr);
  EXPECT_GE(trace->cpu_ms, 0.0);
  EXPECT_FALSE(trace->skipped);
}

TEST(EngineSlicing, ASplitAvgRemapEqualsAnUnsplitOne) {
  const BundledCopy split_scene("cornell_box.gltf"), whole_scene("cornell_box.gltf");
  auto request = [](const std::string& scene, double budget_ms) {
    RenderRequest r = testing::SolverRequest(
        scene, "avg",
        {{"vpls", "48"}, {"grid", "16"}, {"shadow_res", "16"}, {"area_samples", "4"},
         {"direct_shadow_res", "32"}},
        24);
    r.encoding.format = ImageFormat::kExr;
    r.frame_budget_ms = budget_ms;
    return r;
  };
  // 0.01 ms: one VPL map per slice after the first; 10 s: all in one.
  auto split = SharedEngine().Render(request(split_scene.id(), 0.01));
  auto whole = SharedEngine().Render(request(whole_scene.id(), 10'000.0));
  ASSERT_TRUE(split.ok()) << split.status();
  ASSERT_TRUE(whole.ok()) << whole.status();
  const double vpls = FrameStat(*whole, "vpls");
  ASSERT_GT(vpls, 1.0);
  EXPECT_EQ(FrameStat(*whole, "vpl_maps_redrawn"), vpls);   // one slice drew all
  EXPECT_LT(FrameStat(*split, "vpl_maps_redrawn"), vpls);   // the last of several
  EXPECT_EQ(FrameStat(*split, "vpl_maps_pending"), 0.0);
  EXPECT_EQ(FrameStat(*split, "vpls"), vpls);
  // Same VPLs, same maps layer by layer: the same pixels.
  EXPECT_EQ(testing::DecodeExr(*split).rgba, testing::DecodeExr(*whole).rgba);
}

TEST(EngineSlicing, PathtraceKeepsABoundedNumberOfViews) {
  // Each view keeps its own accumulation; a fifth view drops the least
  // recently used one (kMaxViews), so memory does not grow with the views.
  const BundledCopy scene("cornell_box.gltf");
  std::vector<double> views;
  for (int i = 0; i < 6; ++i) {
    RenderRequest request = PathtraceRequest(scene.id(), 1, 0.0);
    CameraUpdate camera;
    camera.look_at = LookAt{{0.2f + 0.05f * float(i), 0.3f, -0.8f}, {0.28f, 0.27f, 0.28f},
                            {0.0f, 1.0f, 0.0f}};
    request.camera = camera;
    auto frame = SharedEngine().Render(request);
    ASSERT_TRUE(frame.ok()) << frame.status();
    views.push_back(FrameStat(*frame, "views"));
  }
  EXPECT_EQ(views, (std::vector<double>{1, 2, 3, 4, 4, 4}));
}

TEST(EngineSlicing, ACancelledRenderStopsAndTheNextOneRuns) {
  const BundledCopy scene("cornell_box.gltf");
  // 4096 spp at 24x24 would take minutes on a CPU; the cancel comes once the
  // work is under way.
  RenderRequest request = PathtraceRequest(scene.id(), 4096, 5.0);
  std::atomic<int> polls{0};
  request.cancelled = [&] { return ++polls > 10; };  // ~10 polls, 20 ms apart
  const auto cancelled = SharedEngine().Render(request);
  EXPECT_EQ(cancelled.status().code(), absl::StatusCode::kCancelled) << cancelled.status();
  // The render thread is free: a small frame comes back (it would wait for
  // the 4096 spp if the cancelled work went on).
  auto next = SharedEngine().Render(PathtraceRequest(scene.id(), 1, 0.0));
  ASSERT_TRUE(next.ok()) << next.status();
  EXPECT_EQ(FrameStat(*next, "spp_frame"), 1.0);
  // No transient session is left behind.
  EXPECT_EQ(SharedEngine().stats().sessions, 0u);
}

}  // namespace
}  // namespace gistream
