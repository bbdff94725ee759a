// What each change makes the engine run: stage timings per frame, skipped
// stages, sequence numbers, shared scene state between sessions.
#include <gtest/gtest.h>

#include <condition_variable>
#include <deque>
#include <mutex>

#include "support/frame_queue.h"
#include "support/render_helpers.h"

namespace gistream {
namespace engine_stages_test {

const StageTiming* FindStage(const EncodedFrame& frame, const std::string& name) {
  for (const StageTiming& t : frame.timings) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

using QueueSink = testing::FrameQueue;

class EngineStagesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto info = testing::SharedEngine().LoadScene(testing::SceneByName("dynamic_block"));
    ASSERT_TRUE(info.ok()) << info.status();
    scene_ = *info;
  }
  SessionId Open(std::shared_ptr<QueueSink> sink) {
    SessionConfig config;
    config.scene = scene_.id;
    config.width = 48;
    config.height = 32;
    config.pacing = Pacing::kOnRequest;
    config.params = {{"area_samples", "4"}, {"shadow_res", "64"}};
    auto opened = testing::SharedEngine().OpenSession(config, sink);
    EXPECT_TRUE(opened.ok()) << opened.status();
    return opened.ok() ? opened->id : "";
  }
  std::shared_ptr<const EncodedFrame> Frame(const SessionId& id, QueueSink& sink) {
    EXPECT_TRUE(testing::SharedEngine().RequestFrames(id, 1).ok());
    return sink.Next();
  }
  SceneInfo scene_;
};

TEST_F(EngineStagesTest, CameraOnlyChangeSkipsShadowMaps) {
  auto sink = std::make_shared<QueueSink>();
  const SessionId id = Open(sink);
  Engine& engine = testing::SharedEngine();
  // First frame: everything runs.
  auto first = Frame(id, *sink);
  ASSERT_TRUE(first);
  for (const char* stage :
       {"apply_updates", "shadow_maps", "gbuffer", "shade", "tonemap", "readback", "encode"}) {
    const StageTiming* t = FindStage(*first, stage);
    ASSERT_NE(t, nullptr) << stage;
    EXPECT_FALSE(t->skipped) << stage;
  }
  // Camera only: shadow maps reused.
  CameraUpdate cam;
  cam.look_at = LookAt{{1.0f, 2.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  ASSERT_TRUE(engine.PushUpdate(id, {7, cam}).ok());
  auto second = Frame(id, *sink);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->last_update_seq, 7u);
  ASSERT_NE(FindStage(*second, "shadow_maps"), nullptr);
  EXPECT_TRUE(FindStage(*second, "shadow_maps")->skipped);
  EXPECT_FALSE(FindStage(*second, "shade")->skipped);
  // A moved node: shadow maps redrawn, scene version bumped.
  NodeTransformUpdate move;
  for (const NodeSummary& n : scene_.nodes) {
    if (n.name == "block") move.node = n.id;
  }
  move.translation = {0.5f, 0.25f, 0.3f};
  ASSERT_TRUE(engine.PushUpdate(id, {8, move}).ok());
  auto third = Frame(id, *sink);
  ASSERT_TRUE(third);
  EXPECT_EQ(third->last_update_seq, 8u);
  EXPECT_GT(third->scene_version, second->scene_version);
  EXPECT_FALSE(FindStage(*third, "shadow_maps")->skipped);
  engine.CloseSession(id);
}

TEST_F(EngineStagesTest, SessionsShareSceneUpdatesButNotCameras) {
  auto sink_a = std::make_shared<QueueSink>();
  auto sink_b = std::make_shared<QueueSink>();
  const SessionId a = Open(sink_a);
  const SessionId b = Open(sink_b);
  Engine& engine = testing::SharedEngine();
  auto a0 = Frame(a, *sink_a);
  auto b0 = Frame(b, *sink_b);
  ASSERT_TRUE(a0 && b0);
  LightUpdate dim;
  dim.light = 0;
  dim.intensity = 1.0f;
  ASSERT_TRUE(engine.PushUpdate(a, {1, dim}).ok());
  auto a1 = Frame(a, *sink_a);
  auto b1 = Frame(b, *sink_b);
  ASSERT_TRUE(a1 && b1);
  // b sees a's light change (same scene version), with its own seq space.
  EXPECT_EQ(a1->scene_version, b1->scene_version);
  EXPECT_GT(b1->scene_version, b0->scene_version);
  EXPECT_EQ(b1->last_update_seq, 0u);
  // Bad updates are refused before they reach the render thread.
  LightUpdate bad;
  bad.light = 999;
  const absl::Status st = engine.PushUpdate(a, {2, bad});
  EXPECT_EQ(st.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("light"), std::string::npos) << st;
  engine.CloseSession(a);
  engine.CloseSession(b);
}

TEST(EngineSolverCache, IdleSolversBeyondTheCapAreDropped) {
  // Twelve parameter sets on one scene, one Render each: every set is a GI
  // solution of its own, but at most max_solvers_per_scene (8) stay cached.
  const testing::BundledCopy scene("dynamic_block.gltf");
  double cached = 0.0;
  for (int samples = 1; samples <= 12; ++samples) {
    EncodedFrame frame;
    testing::RenderRequestExr(
        testing::SolverRequest(scene.id(), "direct",
                               {{"area_samples", std::to_string(samples)}, {"shadow_res", "16"}},
                               8),
        &frame);
    cached = testing::FrameStat(frame, "cached_solvers");
    EXPECT_LE(cached, 8.0) << samples;
  }
  EXPECT_EQ(cached, 8.0);
  // The most recent one is still cached: rendering it again skips its shadow maps.
  EncodedFrame again;
  testing::RenderRequestExr(
      testing::SolverRequest(scene.id(), "direct", {{"area_samples", "12"}, {"shadow_res", "16"}},
                             8),
      &again);
  EXPECT_TRUE(testing::StageSkipped(again, "shadow_maps"));
}

}  // namespace engine_stages_test
}  // namespace gistream
