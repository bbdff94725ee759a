// A still view rests (issue 27): once a continuous session's picture is
// finished (it equalled the frame before, no update came, the solver owes
// no slice or background job) the engine renders nothing for it: its
// keep-alives repeat the last frame's header without GL work, readback or
// encode (counted through EngineStats::frames_rendered, never timed). The
// next update, key-frame request or change by another session on the same
// scene is rendered at once.
#include <gtest/gtest.h>

#include "support/frame_queue.h"
#include "support/render_helpers.h"

namespace gistream {
namespace engine_rest_test {

using testing::BundledCopy;
using testing::FrameQueue;
using testing::FrameStat;
using testing::SharedEngine;

SessionConfig Continuous(const std::string& scene, const std::string& solver) {
  SessionConfig c;
  c.scene = scene;
  c.solver = solver;
  c.width = c.height = 24;
  c.max_fps = 60.0f;
  c.encoding.format = ImageFormat::kPng;
  c.pacing = Pacing::kContinuous;
  return c;
}

bool AtRest(const EncodedFrame& f) { return FrameStat(f, "at_rest") == 1.0; }

// The red wall's colour (material 1 of the bundled Cornell box).
Update RedWall(uint64_t seq, float green) {
  MaterialUpdate m;
  m.material = 1;
  m.base_color = glm::vec4(0.6f, green, 0.05f, 1.0f);
  return Update{seq, m};
}

class EngineRest : public ::testing::TestWithParam<std::string> {
 protected:
  BundledCopy scene_{"cornell_box.gltf"};
};

TEST_P(EngineRest, AStillViewRendersNothingAndKeepAlivesRepeatItsLastFrame) {
  auto sink = std::make_shared<FrameQueue>();
  auto session = SharedEngine().OpenSession(Continuous(scene_.id(), GetParam()), sink);
  ASSERT_TRUE(session.ok()) << session.status();
  // The first keep-alive at rest (about a second after the picture settled).
  auto rest = sink->WaitFor(AtRest);
  ASSERT_TRUE(rest);
  EXPECT_TRUE(rest->unchanged);
  EXPECT_TRUE(rest->image.empty());
  EXPECT_EQ(rest->total_ms, 0.0);
  const EngineStats before = SharedEngine().stats();
  // Two more keep-alives: about two seconds at 60 fps with nothing rendered.
  const size_t seen = sink->Count(AtRest);
  auto later = sink->WaitFor(
      [&](const EncodedFrame& f) { return AtRest(f) && f.frame_number >= rest->frame_number + 2; });
  ASSERT_TRUE(later);
  const EngineStats after = SharedEngine().stats();
  EXPECT_EQ(after.frames_rendered, before.frames_rendered) << "a view at rest was rendered";
  EXPECT_GE(after.keep_alives_at_rest, before.keep_alives_at_rest + 2);
  EXPECT_GE(sink->Count(AtRest), seen + 2);
  EXPECT_EQ(later->scene_version, rest->scene_version);
  // Keep-alives say how long the picture has stood: frames and time since
  // the camera and the scene last changed grow with each one.
  EXPECT_GT(FrameStat(*later, "frames_since_scene_change"),
            FrameStat(*rest, "frames_since_scene_change"));
  EXPECT_GT(FrameStat(*later, "ms_since_camera_change"),
            FrameStat(*rest, "ms_since_camera_change"));
  EXPECT_GE(FrameStat(*rest, "frames_since_camera_change"), 1.0);
  SharedEngine().CloseSession(session->id);
}

TEST_P(EngineRest, AnUpdateAtRestIsRenderedAndTheViewRestsAgain) {
  auto sink = std::make_shared<FrameQueue>();
  auto session = SharedEngine().OpenSession(Continuous(scene_.id(), GetParam()), sink);
  ASSERT_TRUE(session.ok()) << session.status();
  ASSERT_TRUE(sink->WaitFor(AtRest));
  ASSERT_TRUE(SharedEngine().PushUpdate(session->id, RedWall(7, 0.6f)).ok());
  auto changed =
      sink->WaitFor([](const EncodedFrame& f) { return f.last_update_seq == 7 && !f.unchanged; });
  ASSERT_TRUE(changed);
  EXPECT_FALSE(changed->image.empty());
  EXPECT_EQ(FrameStat(*changed, "at_rest"), 0.0);
  EXPECT_EQ(FrameStat(*changed, "frames_since_scene_change"), 0.0);
  EXPECT_GT(FrameStat(*changed, "frames_since_camera_change"), 0.0);
  // It settles again on the new, finished picture.
  auto again =
      sink->WaitFor([](const EncodedFrame& f) { return AtRest(f) && f.last_update_seq == 7; });
  ASSERT_TRUE(again);
  EXPECT_EQ(FrameStat(*again, "update_complete"), 1.0);
  EXPECT_GT(again->scene_version, changed->scene_version - 1);
  SharedEngine().CloseSession(session->id);
}

INSTANTIATE_TEST_SUITE_P(Solvers, EngineRest, ::testing::Values("direct", "implicit_visibility"),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(EngineRestShared, AnotherSessionsChangeToTheSceneWakesARestingView) {
  const BundledCopy scene("cornell_box.gltf");
  auto watcher = std::make_shared<FrameQueue>();
  auto writer = std::make_shared<FrameQueue>();
  auto watching = SharedEngine().OpenSession(Continuous(scene.id(), "direct"), watcher);
  auto writing = SharedEngine().OpenSession(Continuous(scene.id(), "direct"), writer);
  ASSERT_TRUE(watching.ok() && writing.ok());
  auto rest = watcher->WaitFor(AtRest);
  ASSERT_TRUE(rest);
  ASSERT_TRUE(SharedEngine().PushUpdate(writing->id, RedWall(3, 0.5f)).ok());
  // The watcher sent no update, yet shows the new scene version.
  auto woken = watcher->WaitFor(
      [&](const EncodedFrame& f) { return f.scene_version > rest->scene_version && !f.unchanged; });
  ASSERT_TRUE(woken);
  EXPECT_FALSE(woken->image.empty());
  SharedEngine().CloseSession(watching->id);
  SharedEngine().CloseSession(writing->id);
}

TEST(EngineRestShared, AKeyFrameRequestAtRestIsRendered) {
  const BundledCopy scene("cornell_box.gltf");
  auto sink = std::make_shared<FrameQueue>();
  auto session = SharedEngine().OpenSession(Continuous(scene.id(), "direct"), sink);
  ASSERT_TRUE(session.ok()) << session.status();
  auto rest = sink->WaitFor(AtRest);
  ASSERT_TRUE(rest);
  const uint64_t rendered = SharedEngine().stats().frames_rendered;
  ASSERT_TRUE(SharedEngine().RequestKeyFrame(session->id).ok());
  auto key = sink->WaitFor([&](const EncodedFrame& f) {
    return f.frame_number > rest->frame_number && !f.image.empty();
  });
  ASSERT_TRUE(key);
  EXPECT_TRUE(key->key_frame);
  EXPECT_GT(SharedEngine().stats().frames_rendered, rendered);
  SharedEngine().CloseSession(session->id);
}

}  // namespace engine_rest_test
}  // namespace gistream
