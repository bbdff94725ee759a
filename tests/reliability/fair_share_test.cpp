// Fair share of the render thread between tenants (issue 30, item 3): when
// the thread is saturated, a tenant with one stream gets about as much
// render time as a tenant with four, not a fifth of it; with one tenant
// alone nobody waits (work-conserving). Real engine, llvmpipe, 32 x 32
// progressive path tracing (each frame a fixed trace time, never at rest).
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <memory>
#include <thread>
#include <vector>

#include "reliability/reliability_fixture.h"
#include "support/frame_queue.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace fair_share_test {

using namespace std::chrono_literals;

SessionConfig Streaming(const SceneId& scene, const TenantId& tenant) {
  SessionConfig config;
  config.scene = scene;
  config.tenant = tenant;
  config.solver = "pathtrace";
  config.params = {{"time_budget_ms", "6"}};  // every frame costs about as much
  config.width = 32;
  config.height = 32;
  config.max_fps = 240.0f;  // 5 streams x 240 fps x 6 ms: the render thread saturates
  // Float frames: every sample changes them, so none is held back as
  // unchanged (a converged 8-bit picture would hide its render time).
  config.encoding.format = ImageFormat::kExr;
  return config;
}

// The server's time for the frames `sink` received (Frame.total_ms).
double RenderMs(const testing::FrameQueue& sink) {
  double ms = 0.0;
  sink.Count([&](const EncodedFrame& frame) {
    ms += frame.total_ms;
    return true;
  });
  return ms;
}

TEST(FairShare, ATenantWithOneStreamGetsAboutWhatATenantWithFourGets) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  Engine& e = **engine;
  SceneSource source_a = testing::SceneFromBytes(QuadScene().dump());
  source_a.tenant = "tenant-a";
  SceneSource source_b = source_a;
  source_b.tenant = "tenant-b";
  auto scene_a = e.LoadScene(source_a);
  auto scene_b = e.LoadScene(source_b);
  ASSERT_TRUE(scene_a.ok()) << scene_a.status();
  ASSERT_TRUE(scene_b.ok()) << scene_b.status();

  // Tenant a alone: four saturating streams, and nobody waits for a share.
  std::vector<std::shared_ptr<testing::FrameQueue>> a_sinks;
  std::vector<SessionId> ids;
  for (int i = 0; i < 4; ++i) {
    a_sinks.push_back(std::make_shared<testing::FrameQueue>());
    auto session = e.OpenSession(Streaming(scene_a->id, "tenant-a"), a_sinks.back());
    ASSERT_TRUE(session.ok()) << session.status();
    ids.push_back(session->id);
  }
  for (auto& sink : a_sinks) ASSERT_NE(sink->Next(), nullptr);
  std::this_thread::sleep_for(500ms);
  EXPECT_EQ(e.stats().fair_share_deferrals, 0u) << "a tenant alone waited for a share";

  // Tenant b's one stream joins: measured over 3 s once it runs.
  auto b_sink = std::make_shared<testing::FrameQueue>();
  auto b = e.OpenSession(Streaming(scene_b->id, "tenant-b"), b_sink);
  ASSERT_TRUE(b.ok()) << b.status();
  ids.push_back(b->id);
  ASSERT_NE(b_sink->Next(), nullptr);
  double a_start = 0.0;
  for (auto& sink : a_sinks) a_start += RenderMs(*sink);
  const double b_start = RenderMs(*b_sink);
  std::this_thread::sleep_for(3s);
  double a_ms = -a_start;
  for (auto& sink : a_sinks) a_ms += RenderMs(*sink);
  const double b_ms = RenderMs(*b_sink) - b_start;

  // Per session (round robin alone) tenant b would get a quarter of tenant
  // a's render time; per tenant about as much. At least 0.6 of it, and
  // tenant a is not starved either (at least 0.6 of b's).
  std::cout << "render time over 3 s: tenant a (4 streams) " << a_ms << " ms, tenant b (1) " << b_ms
            << " ms, deferrals " << e.stats().fair_share_deferrals << "\n";
  ASSERT_GT(a_ms + b_ms, 1000.0) << "the render thread was not saturated";
  EXPECT_GE(b_ms, 0.6 * a_ms) << "tenant b's one stream got " << b_ms
                              << " ms of render time, tenant a's four " << a_ms;
  EXPECT_GE(a_ms, 0.6 * b_ms) << "tenant a got " << a_ms << " ms, tenant b " << b_ms;
  EXPECT_GT(e.stats().fair_share_deferrals, 0u);

  for (const SessionId& id : ids) e.CloseSession(id);
  e.Shutdown();
}

}  // namespace fair_share_test
}  // namespace gistream::reliability
