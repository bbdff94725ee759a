// The solver work a frame may do (issue 27): a continuous stream capped
// slowly (10 fps) and alone with a frame due gets up to half its frame
// interval (50 ms) instead of the engine's default (30 ms), so a sliced
// solve catches up sooner after an interaction; a session's own
// frame_budget_ms and a faster cap keep their budgets. Every frame says
// its budget (stat budget_ms).
#include <gtest/gtest.h>

#include "support/frame_queue.h"
#include "support/render_helpers.h"

namespace gistream {
namespace frame_budget_test {

using testing::BundledCopy;
using testing::FrameQueue;
using testing::FrameStat;
using testing::SharedEngine;

// The budgets of the first `frames` frames of a continuous `direct` stream.
std::vector<double> Budgets(const std::string& scene, float fps, double frame_budget_ms,
                            int frames) {
  SessionConfig c;
  c.scene = scene;
  c.solver = "direct";
  c.width = c.height = 16;
  c.max_fps = fps;
  c.frame_budget_ms = frame_budget_ms;
  c.encoding.format = ImageFormat::kPng;
  c.pacing = Pacing::kContinuous;
  auto sink = std::make_shared<FrameQueue>();
  auto session = SharedEngine().OpenSession(c, sink);
  EXPECT_TRUE(session.ok()) << session.status();
  std::vector<double> budgets;
  if (!session.ok()) return budgets;
  for (int i = 0; i < frames; ++i) {
    auto frame = sink->Next();
    if (!frame) break;
    budgets.push_back(FrameStat(*frame, "budget_ms"));
  }
  SharedEngine().CloseSession(session->id);
  return budgets;
}

TEST(FrameBudget, ASlowStreamAloneGetsHalfItsIntervalOthersKeepTheirs) {
  const BundledCopy scene("cornell_box.gltf");
  // The only session: every frame of a 10 fps stream has 50 ms.
  for (double b : Budgets(scene.id(), 10.0f, 0.0, 3)) EXPECT_EQ(b, 50.0);
  // Its own budget is kept, at any cap.
  for (double b : Budgets(scene.id(), 10.0f, 20.0, 3)) EXPECT_EQ(b, 20.0);
  // At 30 fps half the interval (16.7 ms) is under the default: 30 ms.
  for (double b : Budgets(scene.id(), 30.0f, 0.0, 3)) EXPECT_EQ(b, 30.0);
  // A very slow cap gets at most 3x the default (not 5 s at 0.1 fps): a
  // session whose frame becomes due meanwhile waits a bounded time.
  for (double b : Budgets(scene.id(), 0.5f, 0.0, 1)) EXPECT_EQ(b, 90.0);
}

}  // namespace frame_budget_test
}  // namespace gistream
