// Many clients at once on one engine (issue 28, item 2): the engine's
// public calls come from the service's worker threads while the render
// thread makes frames and the CPU pool runs solvers' background jobs. Here
// client threads open sessions on a shared scene, push updates, ask for
// frames, render one-shot frames, load and unload scenes and read stats,
// all at once; every call answers, every client sees its last update, and
// the engine is left as it was. In `make test` this checks the outcome; in
// the ThreadSanitizer tree (scripts/ci-sanitizers.sh, thread_engine_tests)
// the same run is checked for data races between those threads.
#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "support/frame_queue.h"
#include "support/render_helpers.h"

namespace gistream {
namespace concurrent_clients_test {

using testing::BundledCopy;
using testing::FrameQueue;
using testing::SharedEngine;

constexpr uint32_t kShortBlock = 5;  // node 5 of the bundled Cornell box
constexpr uint64_t kUpdates = 4;     // per client

SessionConfig Config(const std::string& scene, const std::string& solver, Pacing pacing) {
  SessionConfig c;
  c.scene = scene;
  c.solver = solver;
  c.width = c.height = 16;
  c.max_fps = 60.0f;
  c.encoding.format = ImageFormat::kPng;
  c.pacing = pacing;
  // Small bins keep the relinks short (under ThreadSanitizer they run
  // instrumented, several times slower).
  if (solver == "implicit_visibility") c.params = {{"bins_per_face", "4"}, {"area_samples", "4"}};
  return c;
}

// The client's i-th change: the short block moves, the red wall's colour
// changes, or the light dims, so the solvers redo shapes, materials and
// lights while the other clients' sessions render.
Update Change(int client, uint64_t seq) {
  const float t = 0.002f * static_cast<float>(client * 10 + static_cast<int>(seq));
  switch (seq % 3) {
    case 0: {
      NodeTransformUpdate n;
      n.node = kShortBlock;
      n.translation = glm::vec3(0.185f + t, 0.0825f, 0.169f);
      return Update{seq, n};
    }
    case 1: {
      MaterialUpdate m;
      m.material = 1;
      m.base_color = glm::vec4(0.6f, 0.05f + t, 0.05f, 1.0f);
      return Update{seq, m};
    }
    default: {
      MaterialUpdate m;
      m.material = 0;
      m.base_color = glm::vec4(0.7f - t, 0.7f, 0.7f, 1.0f);
      return Update{seq, m};
    }
  }
}

// One client: a session of `solver`, kUpdates changes, each waited for in
// a frame; a key frame; closed. Failures are counted, not asserted (gtest's
// assertions are for the main thread).
void Client(const std::string& scene, const std::string& solver, Pacing pacing, int client,
            std::atomic<int>& failures) {
  auto sink = std::make_shared<FrameQueue>();
  auto session = SharedEngine().OpenSession(Config(scene, solver, pacing), sink);
  if (!session.ok()) {
    ADD_FAILURE() << "client " << client << ": " << session.status();
    ++failures;
    return;
  }
  for (uint64_t seq = 1; seq <= kUpdates; ++seq) {
    const absl::Status pushed = SharedEngine().PushUpdate(session->id, Change(client, seq));
    const absl::Status asked =
        pacing == Pacing::kOnRequest ? SharedEngine().RequestFrames(session->id, 1) : pushed;
    auto shown = sink->WaitFor([seq](const EncodedFrame& f) { return f.last_update_seq >= seq; });
    if (!pushed.ok() || !asked.ok() || !shown) {
      ADD_FAILURE() << "client " << client << " update " << seq << ": " << pushed << " / " << asked;
      ++failures;
      break;
    }
  }
  const absl::Status key = SharedEngine().RequestKeyFrame(session->id);
  if (!key.ok()) {
    ADD_FAILURE() << "client " << client << " key frame: " << key;
    ++failures;
  }
  for (const auto& [seq, status] : sink->rejected()) {
    ADD_FAILURE() << "client " << client << " update " << seq << " rejected: " << status;
    ++failures;
  }
  SharedEngine().CloseSession(session->id);
}

TEST(ConcurrentClients, SessionsRendersLoadsAndStatsAtOnceAnswerAndLeaveTheEngineAsItWas) {
  const BundledCopy scene("cornell_box.gltf");
  const EngineStats before = SharedEngine().stats();
  std::atomic<int> failures{0};
  std::atomic<bool> done{false};
  std::vector<std::thread> clients;
  // `implicit_visibility` builds its first solve and relinks in background
  // jobs on the CPU pool; `direct` renders every frame on the render thread.
  const std::vector<std::pair<std::string, Pacing>> kinds = {
      {"direct", Pacing::kContinuous},
      {"implicit_visibility", Pacing::kContinuous},
      {"direct", Pacing::kOnRequest},
      {"implicit_visibility", Pacing::kOnRequest}};
  for (size_t i = 0; i < kinds.size(); ++i) {
    clients.emplace_back(Client, scene.id(), kinds[i].first, kinds[i].second, static_cast<int>(i),
                         std::ref(failures));
  }
  // One-shot frames on the same scene, with their own camera.
  std::thread renders([&] {
    for (int i = 0; i < 3; ++i) {
      RenderRequest r;
      r.scene = scene.id();
      r.width = r.height = 16;
      r.encoding.format = ImageFormat::kPng;
      r.updates.push_back(Change(9, static_cast<uint64_t>(i)));
      auto frame = SharedEngine().Render(r);
      if (!frame.ok() || frame->image.empty()) {
        ADD_FAILURE() << "render " << i << ": " << frame.status();
        ++failures;
      }
    }
  });
  // Other scenes come and go while the sessions run.
  std::thread loads([&] {
    for (int i = 0; i < 3; ++i) {
      const BundledCopy other("cornell_box.gltf");
      if (other.id().empty()) {
        ADD_FAILURE() << "load " << i << " failed";
        ++failures;
      }
    }
  });
  // Monitoring reads everything the other threads change.
  std::thread monitor([&] {
    while (!done.load()) {
      const EngineStats s = SharedEngine().stats();
      if (s.scenes == 0) {
        ADD_FAILURE() << "stats lists no scene while one is loaded";
        ++failures;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  for (std::thread& t : clients) t.join();
  renders.join();
  loads.join();
  done = true;
  monitor.join();
  EXPECT_EQ(failures.load(), 0);
  const EngineStats after = SharedEngine().stats();
  EXPECT_EQ(after.sessions, before.sessions);
  EXPECT_EQ(after.scenes, before.scenes);
}

}  // namespace concurrent_clients_test
}  // namespace gistream
