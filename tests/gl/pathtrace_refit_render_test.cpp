// `pathtrace` on a deformation (issue 18): a seek of bending_tube's
// animation refits the BVH (stats bvh_refits / bvh_rebuilds) instead of
// rebuilding it, and the refit solve is the fresh solve of the pose (same
// seed, same rays: the refit BVH answers them as a rebuilt one does,
// tests/unit/pathtrace_refit_test.cpp).
#include <gtest/gtest.h>

#include "support/deforming_scene.h"
#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace pathtrace_refit_render_test {

using testing::BundledCopy;
using testing::FloatImage;
using testing::FrameStat;
using testing::RenderRequestExr;
using testing::SolverRequest;

TEST(PathtraceRefitRender, SeekRefitsAndMatchesAFreshSolve) {
  const std::map<std::string, std::string> params = {{"spp", "8"}};
  const BundledCopy updated("bending_tube.gltf");
  EncodedFrame first, seeked_frame;
  RenderRequestExr(SolverRequest(updated.id(), "pathtrace", params, 32), &first);
  EXPECT_EQ(FrameStat(first, "bvh_rebuilds"), 1.0);
  EXPECT_EQ(FrameStat(first, "bvh_refits"), 0.0);
  const FloatImage seeked = RenderRequestExr(
      SolverRequest(updated.id(), "pathtrace", params, 32, {testing::SeekAnimation(1, 1.0f)}),
      &seeked_frame);
  EXPECT_EQ(FrameStat(seeked_frame, "bvh_rebuilds"), 1.0);
  EXPECT_EQ(FrameStat(seeked_frame, "bvh_refits"), 1.0);
  EXPECT_EQ(FrameStat(seeked_frame, "bvh_refits_declined"), 0.0);
  const double growth = FrameStat(seeked_frame, "bvh_refit_growth");
  testing::RecordMeasurement("bending_tube_refit_growth", growth);
  EXPECT_LE(growth, 2.0);

  const BundledCopy fresh("bending_tube.gltf");
  EncodedFrame fresh_frame;
  const FloatImage direct = RenderRequestExr(
      SolverRequest(fresh.id(), "pathtrace", params, 32, {testing::SeekAnimation(1, 1.0f)}),
      &fresh_frame);
  EXPECT_EQ(FrameStat(fresh_frame, "bvh_refits"), 0.0);
  // The build_bvh stage's CPU time of the refit and of the two builds,
  // recorded (not asserted: timings are the machine's).
  for (const auto& [key, frame] :
       {std::pair{"build_ms_rest", &first}, std::pair{"refit_ms_pose", &seeked_frame},
        std::pair{"build_ms_pose", &fresh_frame}}) {
    const StageTiming* stage = testing::FrameStage(*frame, "build_bvh");
    ASSERT_NE(stage, nullptr);
    EXPECT_FALSE(stage->skipped);
    testing::RecordMeasurement(key, stage->cpu_ms);
  }
  // Same seed and the same hits: the same image but for a path that met a
  // shared edge, where either tree may report the other triangle (none
  // were seen; 1e-6 leaves room for one such path at 8 spp).
  const double error = testing::RelMse(seeked, direct);
  testing::RecordMeasurement("refit_vs_fresh_rel_mse", error);
  EXPECT_LE(error, 1e-6);
}

}  // namespace pathtrace_refit_render_test
}  // namespace gistream
