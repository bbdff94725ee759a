// `avg` after a moved node, through the real engine (issue 12): only the
// moved box is voxelized again, the light paths that avoid it and the maps
// of VPLs that stayed where they were and cannot see it are kept, and the
// image equals a full solve of the moved scene.
#include <gtest/gtest.h>

#include "support/render_helpers.h"

namespace gistream {
namespace avg_incremental_render_test {

using testing::BundledCopy;
using testing::FrameStat;

RenderRequest AvgRequest(const std::string& scene, double budget_ms, std::vector<Update> updates) {
  RenderRequest r = testing::SolverRequest(scene, "avg",
                                           {{"vpls", "256"},
                                            {"grid", "32"},
                                            {"shadow_res", "16"},
                                            {"area_samples", "4"},
                                            {"still_vpls", "0"},
                                            {"direct_shadow_res", "32"}},
                                           24, std::move(updates));
  r.frame_budget_ms = budget_ms;
  return r;
}

TEST(AvgIncrementalRender, AMovedBlockKeepsValidVplsAndEqualsAFullSolve) {
  const BundledCopy moved_scene("cornell_box.gltf"), fresh_scene("cornell_box.gltf");
  NodeTransformUpdate move;
  move.node = 6;  // tall_block, inside the walls: the grid keeps its place
  move.translation = glm::vec3(-0.05f, 0.0f, 0.05f);
  testing::RenderRequestExr(AvgRequest(moved_scene.id(), 10'000.0, {}));
  EncodedFrame incremental_frame, fresh_frame;
  // The incremental update in slices of the budget (0.01 ms: one map per
  // slice after the first), the fresh solve in one.
  const testing::FloatImage incremental = testing::RenderRequestExr(
      AvgRequest(moved_scene.id(), 0.01, {{1, move}}), &incremental_frame);
  const testing::FloatImage fresh =
      testing::RenderRequestExr(AvgRequest(fresh_scene.id(), 10'000.0, {{1, move}}), &fresh_frame);

  const double vpls = FrameStat(fresh_frame, "vpls");
  ASSERT_GT(vpls, 1.0);
  EXPECT_EQ(FrameStat(incremental_frame, "vpls"), vpls);
  EXPECT_EQ(FrameStat(incremental_frame, "voxelize_partial"), 1.0);
  EXPECT_EQ(FrameStat(fresh_frame, "voxelize_partial"), 0.0);
  EXPECT_LT(FrameStat(incremental_frame, "voxels_rewritten"), 0.5 * 32 * 32 * 32);
  // Some paths crossed the block's old or new place, many did not.
  EXPECT_GT(FrameStat(incremental_frame, "vpl_paths_retraced"), 0.0);
  EXPECT_GT(FrameStat(incremental_frame, "vpl_paths_kept"), 0.0);
  EXPECT_GT(FrameStat(incremental_frame, "vpls_kept"), 0.0);
  EXPECT_EQ(
      FrameStat(incremental_frame, "vpls_kept") + FrameStat(incremental_frame, "vpls_retraced"),
      vpls);
  // Maps kept: VPLs whose hemisphere does not hold the block's boxes.
  EXPECT_GT(FrameStat(incremental_frame, "vpl_maps_kept"), 0.0);
  EXPECT_LT(FrameStat(incremental_frame, "vpl_maps_kept"), vpls);
  EXPECT_EQ(FrameStat(incremental_frame, "vpl_maps_pending"), 0.0);
  EXPECT_EQ(FrameStat(incremental_frame, "update_complete"), 1.0);
  EXPECT_EQ(FrameStat(fresh_frame, "vpl_maps_kept"), 0.0);
  // The same VPLs (bitwise: the unit test AvgIncremental.*), each map
  // copied or drawn from the same geometry: the same image to float
  // rounding (relative 1e-4).
  testing::ExpectSameImage(incremental, fresh);
}

}  // namespace avg_incremental_render_test
}  // namespace gistream
