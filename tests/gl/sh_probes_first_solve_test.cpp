// sh_probes' first solve spread over frames (issue 12): the probes are
// rasterized, then bounced (each bounce interpolating from the previous
// one's coefficients, Jacobi as in Section 3), in batches of probes that do
// not depend on the budget, so a first solve split into many slices
// reaches the image of an unsplit one.
#include <gtest/gtest.h>

#include "support/render_helpers.h"

namespace gistream {
namespace sh_probes_first_solve_test {

using testing::BundledCopy;
using testing::FrameStat;

RenderRequest ProbesRequest(const std::string& scene, double budget_ms) {
  RenderRequest r = testing::SolverRequest(scene, "sh_probes",
                                           {{"grid", "4"},
                                            {"face_size", "8"},
                                            {"area_samples", "4"},
                                            {"shadow_res", "32"},
                                            {"tolerance", "0.001"}},
                                           24);
  r.frame_budget_ms = budget_ms;
  return r;
}

TEST(ShProbesFirstSolve, ASplitFirstSolveConvergesToAnUnsplitOne) {
  const BundledCopy split_scene("cornell_box.gltf"), whole_scene("cornell_box.gltf");
  EncodedFrame split_frame, whole_frame;
  // 0.01 ms: one batch of probes per slice; 10 s: the whole solve in one.
  const testing::FloatImage split =
      testing::RenderRequestExr(ProbesRequest(split_scene.id(), 0.01), &split_frame);
  const testing::FloatImage whole =
      testing::RenderRequestExr(ProbesRequest(whole_scene.id(), 10'000.0), &whole_frame);
  ASSERT_EQ(FrameStat(whole_frame, "probes"), 64.0);
  for (const EncodedFrame* f : {&split_frame, &whole_frame}) {
    EXPECT_EQ(FrameStat(*f, "full_solve_pending"), 0.0);
    EXPECT_EQ(FrameStat(*f, "update_complete"), 1.0);
    EXPECT_EQ(FrameStat(*f, "cap_reached"), 0.0);
  }
  // The whole solve ran every batch in one Update (64 probes rasterized in
  // batches of 9, then at least two bounces); the split one's last slice
  // one batch.
  EXPECT_GE(FrameStat(whole_frame, "probe_batches"), 8.0 + 2.0 * 6.0);
  EXPECT_EQ(FrameStat(split_frame, "probe_batches"), 1.0);
  EXPECT_EQ(FrameStat(split_frame, "bounces_run"), FrameStat(whole_frame, "bounces_run"));
  EXPECT_GE(FrameStat(whole_frame, "bounces_run"), 2.0);
  // The same batches in the same order, only in different frames: the same
  // coefficients and image to float rounding (relative 1e-4).
  testing::ExpectSameImage(split, whole);
}

}  // namespace sh_probes_first_solve_test
}  // namespace gistream
