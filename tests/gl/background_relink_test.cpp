// implicit_visibility relinks a moved scene in a background job on the CPU
// pool while a continuous session keeps getting frames of the last
// solution; once the links are in, the image equals what a fresh solver
// renders for the moved scene (a split update converges to the unsplit one).
#include <gtest/gtest.h>

#include "support/frame_queue.h"
#include "support/render_helpers.h"

namespace gistream {
namespace {

using testing::BundledCopy;
using testing::FloatImage;

double Stat(const EncodedFrame& frame, const std::string& name) {
  for (const auto& [k, v] : frame.stats) {
    if (k == name) return v;
  }
  return -1.0;
}

const std::map<std::string, std::string> kParams = {
    {"bins_per_face", "6"}, {"area_samples", "8"}, {"shadow_res", "64"}};

NodeTransformUpdate MoveBlock() {
  NodeTransformUpdate move;
  move.node = 6;  // tall_block
  move.translation = glm::vec3(0.20f, 0.0f, 0.30f);
  return move;
}

TEST(BackgroundRelink, AStreamKeepsItsFramesAndConvergesToAFreshSolve) {
  const BundledCopy scene("cornell_box.gltf"), fresh_scene("cornell_box.gltf");
  SessionConfig config = testing::ExrStreamConfig(scene.id(), "implicit_visibility", kParams, 32);
  auto sink = std::make_shared<testing::FrameQueue>();
  auto opened = testing::SharedEngine().OpenSession(config, sink);
  ASSERT_TRUE(opened.ok()) << opened.status();
  // The first solve links in the background too (tests/gl/first_solve_test):
  // wait for its complete frame.
  auto first =
      sink->WaitFor([](const EncodedFrame& f) { return Stat(f, "update_complete") == 1.0; });
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(Stat(*first, "links_pending"), 0.0);

  ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, {1, MoveBlock()}).ok());
  // Frames keep coming while the links are rebuilt; the last of them takes
  // the links and gathers the light.
  auto done = sink->WaitFor([](const EncodedFrame& f) {
    return f.last_update_seq >= 1 && Stat(f, "links_pending") == 0.0 &&
           Stat(f, "gi_versions_behind") == 0.0;
  });
  testing::SharedEngine().CloseSession(opened->id);
  ASSERT_NE(done, nullptr);
  const StageTiming* links = testing::FrameStage(*done, "create_links");
  ASSERT_NE(links, nullptr);
  // Every frame that showed the move while its links were pending said so.
  EXPECT_EQ(sink->Count([](const EncodedFrame& f) {
    return f.last_update_seq >= 1 && Stat(f, "links_pending") == 1.0 &&
           Stat(f, "gi_versions_behind") == 0.0;
  }),
            0u);

  RenderRequest fresh = testing::SolverRequest(fresh_scene.id(), "implicit_visibility", kParams, 32,
                                               {{1, MoveBlock()}});
  EncodedFrame fresh_frame;
  // Same links, same gather: equal to float rounding (1e-4 relative).
  testing::ExpectSameImage(testing::DecodeExr(*done),
                           testing::RenderRequestExr(fresh, &fresh_frame));
}

TEST(BackgroundRelink, ARenderAfterAMoveIsComplete) {
  const BundledCopy scene("cornell_box.gltf"), fresh_scene("cornell_box.gltf");
  testing::RenderRequestExr(testing::SolverRequest(scene.id(), "implicit_visibility", kParams, 32));
  EncodedFrame moved_frame, fresh_frame;
  const FloatImage moved = testing::RenderRequestExr(
      testing::SolverRequest(scene.id(), "implicit_visibility", kParams, 32, {{1, MoveBlock()}}),
      &moved_frame);
  const FloatImage fresh =
      testing::RenderRequestExr(testing::SolverRequest(fresh_scene.id(), "implicit_visibility",
                                                       kParams, 32, {{1, MoveBlock()}}),
                                &fresh_frame);
  EXPECT_EQ(Stat(moved_frame, "links_pending"), 0.0);
  EXPECT_FALSE(testing::FrameStage(moved_frame, "create_links")->skipped);
  testing::ExpectSameImage(moved, fresh);
}

}  // namespace
}  // namespace gistream
