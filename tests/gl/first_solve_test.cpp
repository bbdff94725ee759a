// The first solve of a GI solver is a background job like any later
// update: the render thread, which every session shares, never waits for
// it. With the CPU pool's workers held (so no job can run), sessions that
// open `avg`, `implicit_visibility` and `antiradiance` still get frames
// (direct light alone, update_complete 0), and a `direct` stream beside
// them still answers a camera update. Once the pool is released each
// reaches a complete frame that adds the indirect light to the direct-only
// one, equal to a Render of a fresh solver. A solver dropped while its job
// runs is kept until the job ends, not waited for.
#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "support/frame_queue.h"
#include "support/held_pool.h"
#include "support/render_helpers.h"

namespace gistream {
namespace first_solve_test {

using testing::FrameStat;

constexpr uint32_t kSize = 24;

struct GiSession {
  GiSession(std::string s, std::map<std::string, std::string> p)
      : solver(std::move(s)), params(std::move(p)) {}
  std::string solver;
  std::map<std::string, std::string> params;
  std::shared_ptr<testing::FrameQueue> sink = std::make_shared<testing::FrameQueue>();
  std::string id;
};

double Mean(const testing::FloatImage& image) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const glm::vec3 v = image.at(x, y);
      sum += double(v.r + v.g + v.b);
    }
  }
  return sum / std::max(1.0, 3.0 * image.width * image.height);
}

// A `direct` stream beside the sessions under test, its first frame in.
struct DirectStream {
  explicit DirectStream(const std::string& scene) {
    auto opened = testing::SharedEngine().OpenSession(
        testing::ExrStreamConfig(scene, "direct", {}, kSize), sink);
    EXPECT_TRUE(opened.ok()) << opened.status();
    if (opened.ok()) id = opened->id;
    EXPECT_NE(sink->Next(), nullptr);
  }
  ~DirectStream() { testing::SharedEngine().CloseSession(id); }
  // Moves the camera (update `seq`) and expects the frame that applies it:
  // the render thread is serving this stream.
  void ExpectAnUpdateAnswered(uint64_t seq) {
    CameraUpdate camera;
    camera.look_at =
        LookAt{{0.0f, 1.0f, 3.0f + 0.1f * float(seq)}, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
    ASSERT_TRUE(testing::SharedEngine().PushUpdate(id, {seq, camera}).ok());
    EXPECT_NE(sink->WaitFor([seq](const EncodedFrame& f) { return f.last_update_seq >= seq; }),
              nullptr);
  }
  std::shared_ptr<testing::FrameQueue> sink = std::make_shared<testing::FrameQueue>();
  SessionId id;
};

TEST(FirstSolves, NeverStallTheRenderThreadAndEndAsAFreshSolve) {
  const testing::BundledCopy scene("cornell_box.gltf"), fresh_scene("cornell_box.gltf");
  Engine& engine = testing::SharedEngine();
  DirectStream direct(scene.id());

  std::vector<GiSession> sessions = {
      {"avg", {{"vpls", "128"}, {"grid", "32"}, {"shadow_res", "16"}}},
      {"implicit_visibility", {{"bins_per_face", "6"}, {"area_samples", "8"}}},
      {"antiradiance", {{"bins", "64"}, {"area_samples", "8"}}},
  };
  {
    testing::HeldPool held;
    for (GiSession& s : sessions) {
      auto opened = engine.OpenSession(
          testing::ExrStreamConfig(scene.id(), s.solver, s.params, kSize), s.sink);
      ASSERT_TRUE(opened.ok()) << s.solver << ": " << opened.status();
      s.id = opened->id;
      // A first frame comes while the job cannot run: the Update returned.
      auto first = s.sink->Next();
      ASSERT_NE(first, nullptr) << s.solver;
      if (testing::HeldPool::Holds()) {
        EXPECT_EQ(FrameStat(*first, "update_complete"), 0.0) << s.solver;
      }
    }
    // The direct stream beside them still answers an update.
    direct.ExpectAnUpdateAnswered(1);
  }
  for (GiSession& s : sessions) {
    auto complete = s.sink->WaitFor(
        [](const EncodedFrame& f) { return FrameStat(f, "update_complete") == 1.0; });
    engine.CloseSession(s.id);
    ASSERT_NE(complete, nullptr) << s.solver;
    const testing::FloatImage solved = testing::DecodeExr(*complete);
    if (testing::HeldPool::Holds()) {
      // The frames before it showed direct light alone; the solution adds
      // the indirect light (about a third of the Cornell box's mean).
      const testing::FloatImage direct_only = testing::DecodeExr(*s.sink->WaitFor(
          [](const EncodedFrame& f) { return FrameStat(f, "update_complete") == 0.0; }));
      EXPECT_GT(Mean(solved), 1.1 * Mean(direct_only)) << s.solver;
    }
    testing::ExpectSameImage(solved, testing::RenderRequestExr(testing::SolverRequest(
                                         fresh_scene.id(), s.solver, s.params, kSize)));
  }
}

// A scene dropped while its solver's job still runs: the engine keeps the
// solver until the job ends (its destructor would wait for it), so the
// render thread goes on serving the other sessions.
TEST(FirstSolves, DroppingASolverWhoseJobRunsNeverStallsTheRenderThread) {
  const testing::BundledCopy other("cornell_box.gltf");
  Engine& engine = testing::SharedEngine();
  DirectStream direct(other.id());
  {
    testing::HeldPool held;
    {
      const testing::BundledCopy scene("cornell_box.gltf");
      auto sink = std::make_shared<testing::FrameQueue>();
      auto opened = engine.OpenSession(
          testing::ExrStreamConfig(scene.id(), "antiradiance", {{"bins", "64"}}, kSize), sink);
      ASSERT_TRUE(opened.ok()) << opened.status();
      // Its first solve's job has started (after the shadow maps) and
      // cannot run.
      if (testing::HeldPool::Holds()) {
        ASSERT_NE(sink->WaitFor(
                      [](const EncodedFrame& f) { return FrameStat(f, "links_pending") == 1.0; }),
                  nullptr);
      }
      engine.CloseSession(opened->id);
    }  // the scene is unloaded: its GPU record and solver dropped
    direct.ExpectAnUpdateAnswered(1);
    // The drop runs on the render thread once the closed session is gone
    // there too: the solver is kept, its job still held (polled: a hang
    // bound, not a timing threshold).
    if (testing::HeldPool::Holds()) {
      for (int i = 0; i < 2000 && engine.stats().retiring_solvers == 0; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
      EXPECT_EQ(engine.stats().retiring_solvers, 1u);
      // And the render thread still serves the direct stream after it.
      direct.ExpectAnUpdateAnswered(2);
    }
  }
  // Released, the job ends and the kept solver is destroyed at a tick.
  for (int i = 0; i < 2000 && engine.stats().retiring_solvers > 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(engine.stats().retiring_solvers, 0u);
}

}  // namespace first_solve_test
}  // namespace gistream
