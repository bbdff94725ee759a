// Budgeted, sliced frames through the real engine: a path-traced Render,
// an avg VPL re-map, an sh_probes update after a move and an antiradiance
// relink in the background split into many slices give the same image as
// one unsplit frame; their stats and timings cover every slice; a cancelled
// Render stops and leaves the render thread free for the next request.
#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "support/render_helpers.h"

namespace gistream {
namespace engine_slicing_test {

using testing::BundledCopy;
using testing::FrameStat;
using testing::SharedEngine;

RenderRequest PathtraceRequest(const std::string& scene, int spp, double budget_ms) {
  RenderRequest request =
      testing::SolverRequest(scene, "pathtrace", {{"spp", std::to_string(spp)}, {"seed", "3"}}, 24);
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
    RenderRequest r = testing::SolverRequest(scene, "avg",
                                             {{"vpls", "48"},
                                              {"still_vpls", "0"},
                                              {"grid", "16"},
                                              {"shadow_res", "16"},
                                              {"area_samples", "4"},
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
  EXPECT_EQ(FrameStat(*whole, "vpl_maps_redrawn"), vpls);  // one slice drew all
  EXPECT_LT(FrameStat(*split, "vpl_maps_redrawn"), vpls);  // the last of several
  EXPECT_EQ(FrameStat(*split, "vpl_maps_pending"), 0.0);
  EXPECT_EQ(FrameStat(*split, "vpls"), vpls);
  // Same VPLs, same maps layer by layer: the same pixels.
  EXPECT_EQ(testing::DecodeExr(*split).rgba, testing::DecodeExr(*whole).rgba);
}

// sh_probes after a move: the probes that see the block are re-rasterized
// and every probe re-rendered in batches of the frame budget (Gauss-Seidel
// sweeps from the last solution until a sweep changes L_00 by less than the
// tolerance), the shown SH following with hysteresis. The converged image
// does not depend on how many frames the update took, and matches a fresh
// solve of the moved scene.
TEST(EngineSlicing, ASplitShProbesUpdateConvergesToAnUnsplitOne) {
  const BundledCopy split_scene("cornell_box.gltf"), whole_scene("cornell_box.gltf"),
      fresh_scene("cornell_box.gltf");
  auto request = [](const std::string& scene, double budget_ms, std::vector<Update> updates) {
    RenderRequest r = testing::SolverRequest(scene, "sh_probes",
                                             {{"grid", "4"},
                                              {"face_size", "8"},
                                              {"area_samples", "4"},
                                              {"shadow_res", "32"},
                                              {"tolerance", "0.001"}},
                                             24, std::move(updates));
    r.frame_budget_ms = budget_ms;
    return r;
  };
  // Inside the walls, so the probe grid keeps its layout (a new layout is
  // a full solve).
  NodeTransformUpdate move;
  move.node = 6;  // tall_block
  move.translation = glm::vec3(-0.05f, 0.0f, 0.05f);
  // The first solve: in batches of probes over many slices in the first,
  // in one in the second; the same solution (ShProbesFirstSolve.*).
  testing::RenderRequestExr(request(split_scene.id(), 0.01, {}));
  testing::RenderRequestExr(request(whole_scene.id(), 10'000.0, {}));
  EncodedFrame split_frame, whole_frame, fresh_frame;
  // 0.01 ms: one batch per slice; 10 s: the whole update in one.
  const testing::FloatImage split =
      testing::RenderRequestExr(request(split_scene.id(), 0.01, {{1, move}}), &split_frame);
  const testing::FloatImage whole =
      testing::RenderRequestExr(request(whole_scene.id(), 10'000.0, {{1, move}}), &whole_frame);
  const testing::FloatImage fresh =
      testing::RenderRequestExr(request(fresh_scene.id(), 0.0, {{1, move}}), &fresh_frame);
  const double probes = FrameStat(whole_frame, "probes");
  ASSERT_EQ(probes, 64.0);
  for (const EncodedFrame* f : {&split_frame, &whole_frame}) {
    EXPECT_EQ(FrameStat(*f, "probes_pending"), 0.0);
    EXPECT_EQ(FrameStat(*f, "shadow_maps_pending"), 0.0);
    EXPECT_EQ(FrameStat(*f, "update_complete"), 1.0);
    // The block is seen by some probes, not by all (those behind the short
    // block or inside a block do not see it).
    EXPECT_GT(FrameStat(*f, "probes_affected"), 0.0);
    EXPECT_LE(FrameStat(*f, "probes_affected"), probes);
  }
  EXPECT_EQ(FrameStat(split_frame, "probes_affected"), FrameStat(whole_frame, "probes_affected"));
  // The whole update ran every batch of every sweep in one Update; the
  // split one's last slice one batch.
  EXPECT_GE(FrameStat(whole_frame, "probes_updated"), 2.0 * probes);
  EXPECT_GT(FrameStat(whole_frame, "probe_batches"), 2.0);
  EXPECT_EQ(FrameStat(split_frame, "probe_batches"), 1.0);
  // Split and whole reach the fixed point by different paths (the split
  // one's probes take the new shadow maps only once those are all drawn):
  // each stops within the tolerance (0.1 % of L_00 per sweep), so they
  // agree to a few tenths of a percent of the radiance.
  testing::ExpectSameImage(split, whole, 5e-3f);
  // A fresh solve (Jacobi bounces from zero, same tolerance) of the moved
  // scene: the same fixed point within about the same.
  testing::ExpectSameImage(split, fresh, 1e-2f);
}

// antiradiance after a move: the shadow maps are redrawn in slices of the
// budget and the links of the moved block's root pairs rebuilt, with the
// transport (iterating from the shown solution), as a background job on the
// CPU pool; the solution shown once both are in equals the one an unsplit
// update gives, and a fresh solve's within the tolerance.
TEST(EngineSlicing, AnAntiradianceUpdateInTheBackgroundEqualsAnUnsplitOne) {
  const BundledCopy split_scene("cornell_box.gltf"), whole_scene("cornell_box.gltf"),
      fresh_scene("cornell_box.gltf");
  auto request = [](const std::string& scene, double budget_ms, std::vector<Update> updates) {
    RenderRequest r = testing::SolverRequest(
        scene, "antiradiance",
        {{"bins", "32"}, {"area_samples", "4"}, {"shadow_res", "32"}, {"tolerance", "0.001"}}, 24,
        std::move(updates));
    r.frame_budget_ms = budget_ms;
    return r;
  };
  NodeTransformUpdate move;
  move.node = 6;  // tall_block
  move.translation = glm::vec3(-0.05f, 0.0f, 0.05f);
  testing::RenderRequestExr(request(split_scene.id(), 0.01, {}));
  testing::RenderRequestExr(request(whole_scene.id(), 10'000.0, {}));
  EncodedFrame split_frame, whole_frame, fresh_frame;
  const testing::FloatImage split =
      testing::RenderRequestExr(request(split_scene.id(), 0.01, {{1, move}}), &split_frame);
  const testing::FloatImage whole =
      testing::RenderRequestExr(request(whole_scene.id(), 10'000.0, {{1, move}}), &whole_frame);
  const testing::FloatImage fresh =
      testing::RenderRequestExr(request(fresh_scene.id(), 0.0, {{1, move}}), &fresh_frame);
  for (const EncodedFrame* f : {&split_frame, &whole_frame}) {
    EXPECT_EQ(FrameStat(*f, "links_pending"), 0.0);
    EXPECT_EQ(FrameStat(*f, "shadow_maps_pending"), 0.0);
    // Only the pairs with the block's root were relinked.
    EXPECT_GT(FrameStat(*f, "relinked_root_pairs"), 0.0);
    EXPECT_LT(FrameStat(*f, "relinked_root_pairs"), FrameStat(*f, "root_pairs"));
    EXPECT_FALSE(testing::FrameStage(*f, "link")->skipped);
  }
  EXPECT_EQ(FrameStat(fresh_frame, "relinked_root_pairs"), FrameStat(fresh_frame, "root_pairs"));
  // The same links (kept and relinked pairs equal a full link), the same
  // direct light once the new maps are shown, the same iterations from the
  // same solution: equal to float rounding.
  testing::ExpectSameImage(split, whole);
  // A fresh solve iterates from the sources: the same fixed point, each
  // stopped within the tolerance (0.1 % of the source per iteration).
  testing::ExpectSameImage(split, fresh, 5e-3f);
}

TEST(EngineSlicing, PathtraceKeepsABoundedNumberOfViews) {
  // Each view keeps its own accumulation; a fifth view drops the least
  // recently used one (kMaxViews), so memory does not grow with the views.
  const BundledCopy scene("cornell_box.gltf");
  std::vector<double> views;
  for (int i = 0; i < 6; ++i) {
    RenderRequest request = PathtraceRequest(scene.id(), 1, 0.0);
    CameraUpdate camera;
    camera.look_at =
        LookAt{{0.2f + 0.05f * float(i), 0.3f, -0.8f}, {0.28f, 0.27f, 0.28f}, {0.0f, 1.0f, 0.0f}};
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

}  // namespace engine_slicing_test
}  // namespace gistream
