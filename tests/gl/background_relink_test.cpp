// implicit_visibility relinks a moved scene in a background job on the CPU
// pool while a continuous session keeps getting frames of the last
// solution; once the links are in, the image equals what a fresh solver
// renders for the moved scene (a split update converges to the unsplit one).
#include <gtest/gtest.h>

#include "support/frame_queue.h"
#include "support/held_pool.h"
#include "support/render_helpers.h"

namespace gistream {
namespace background_relink_test {

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

// Under continuous motion every relink ends with the next one queued: the
// links it delivers are gathered at once (issue 27), not only links with
// no relink behind them, which had left the first solution on screen
// until the motion stopped.
TEST(BackgroundRelink, LinksAreGatheredWhileANewerRelinkRuns) {
  const BundledCopy scene("cornell_box.gltf");
  SessionConfig config = testing::ExrStreamConfig(scene.id(), "implicit_visibility", kParams, 32);
  auto sink = std::make_shared<testing::FrameQueue>();
  auto opened = testing::SharedEngine().OpenSession(config, sink);
  ASSERT_TRUE(opened.ok()) << opened.status();
  ASSERT_NE(sink->WaitFor([](const EncodedFrame& f) { return Stat(f, "update_complete") == 1.0; }),
            nullptr);
  // (A one-thread CPU pool runs a job inline: nothing to hold.)
  if (!testing::HeldPool::Holds()) GTEST_SKIP() << "one CPU: background jobs run inline";
  testing::HeldPool held;
  // Move 1 starts relink A, which cannot run yet; move 2 queues another.
  ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, {1, MoveBlock()}).ok());
  ASSERT_NE(sink->WaitFor([](const EncodedFrame& f) { return f.last_update_seq >= 1; }), nullptr);
  NodeTransformUpdate again = MoveBlock();
  again.translation.x += 0.05f;
  ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, {2, again}).ok());
  auto before = sink->WaitFor([](const EncodedFrame& f) { return f.last_update_seq >= 2; });
  ASSERT_NE(before, nullptr);
  EXPECT_EQ(Stat(*before, "gi_versions_behind"), 2.0);  // the first solve's GI
  held.Release();
  // The frame that takes A's links starts relink B for move 2 and gathers
  // A's: one version behind, B pending.
  auto took = sink->WaitFor([](const EncodedFrame& f) {
    const StageTiming* links = testing::FrameStage(f, "create_links");
    return f.last_update_seq >= 2 && links != nullptr && !links->skipped;
  });
  ASSERT_NE(took, nullptr);
  EXPECT_EQ(Stat(*took, "links_pending"), 1.0);
  EXPECT_EQ(Stat(*took, "gi_versions_behind"), 1.0);
  EXPECT_FALSE(testing::FrameStage(*took, "illumination")->skipped);
  // B's links follow and the solution is current.
  ASSERT_NE(sink->WaitFor([](const EncodedFrame& f) {
    return f.last_update_seq >= 2 && Stat(f, "update_complete") == 1.0 &&
           Stat(f, "gi_versions_behind") == 0.0;
  }),
            nullptr);
  testing::SharedEngine().CloseSession(opened->id);
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

}  // namespace background_relink_test
}  // namespace gistream
