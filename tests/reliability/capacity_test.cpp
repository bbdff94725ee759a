// Admission by GPU time (issue 31, item 5): with --max-render-busy set, a
// session is refused RESOURCE_EXHAUSTED (naming the flag, with a retry
// hint) while the render thread's measured busy share plus one more active
// session's share would pass the limit, and admitted again once the others
// rest (a still, finished picture costs no render time). Real engine,
// llvmpipe, 32 x 32.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

#include "reliability/reliability_fixture.h"
#include "support/frame_queue.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace capacity_test {

using namespace std::chrono_literals;

template <typename Pred>
bool Eventually(Pred pred, std::chrono::milliseconds limit = 60s) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!pred() && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(10ms);
  return pred();
}

SessionConfig Config(const std::string& scene) {
  SessionConfig config;
  config.scene = scene;
  config.solver = "direct";
  config.width = 32;
  config.height = 32;
  config.max_fps = 60.0f;
  config.encoding.format = ImageFormat::kPng;
  return config;
}

TEST(Capacity, ASessionPastTheRenderBusyLimitIsRefusedUntilTheOthersRest) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  options.max_render_busy = 0.01;  // 1 %: one refining session passes it
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  Engine& e = **engine;
  auto scene = e.LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_EQ(e.stats().max_render_busy, 0.01);

  // The first session is admitted whatever the load (nothing active).
  auto first_sink = std::make_shared<testing::FrameQueue>();
  auto first = e.OpenSession(Config(scene->id), first_sink);
  ASSERT_TRUE(first.ok()) << first.status();
  ASSERT_NE(first_sink->Next(), nullptr);
  // While it renders (its first frame, then refinement) the render thread
  // is measurably busy and the session counts as active.
  auto second_sink = std::make_shared<testing::FrameQueue>();
  absl::StatusOr<SessionOpenInfo> refused = absl::UnknownError("not tried");
  ASSERT_TRUE(Eventually([&] {
    const EngineStats stats = e.stats();
    if (stats.active_sessions != 1 || stats.render_busy_ratio <= 0.02) return false;
    refused = e.OpenSession(Config(scene->id), second_sink);
    return !refused.ok();
  })) << "a second session was admitted at busy "
      << e.stats().render_busy_ratio;
  EXPECT_STATUS(refused.status(), kResourceExhausted, "--max-render-busy");
  EXPECT_STATUS(refused.status(), kResourceExhausted, "Retry in a few seconds, or on another");
  const double busy = e.stats().render_busy_ratio;
  EXPECT_GT(busy, 0.0);
  EXPECT_LE(busy, 1.0);

  // Once the still view has refined and rests, it costs nothing: admitted.
  ASSERT_TRUE(Eventually([&] { return e.stats().active_sessions == 0; }))
      << "the first session never came to rest";
  auto second = e.OpenSession(Config(scene->id), second_sink);
  EXPECT_TRUE(second.ok()) << second.status();

  if (second.ok()) e.CloseSession(second->id);
  e.CloseSession(first->id);
  e.Shutdown();
}

}  // namespace capacity_test
}  // namespace gistream::reliability
