// Issue 13, finding 6 (in part): a LoadScene racing an UnloadScene of the
// id it is about to get (ids were predictable; since issue 15 they are
// random, but the id is listed by stats() while the upload runs), or racing
// shutdown, could
// leave a GPU copy nobody frees, or a call waiting for a render-thread job
// that never runs. Every call must finish with OK or a clear status.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "reliability/reliability_fixture.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace load_unload_race_test {

using std::chrono::seconds;

// The ids stats() lists.
std::set<std::string> ListedIds() {
  const std::vector<std::string> ids = E().stats().scene_ids;
  return {ids.begin(), ids.end()};
}

TEST(LoadUnloadRace, UnloadOfTheIdBeingLoadedFinishesEveryCallAndLeaksNothing) {
  // GL bytes are refreshed by each upload job, which runs after every job
  // queued before it (unloads included): two loads give one scene's bytes.
  const QuadCopy first;
  ASSERT_FALSE(first.id().empty());
  const uint64_t bytes_one = E().stats().gl_object_bytes;
  const QuadCopy second;
  const uint64_t bytes_two = E().stats().gl_object_bytes;
  const uint64_t scene_bytes = bytes_two - bytes_one;
  ASSERT_GT(scene_bytes, 0u);
  const uint32_t scenes_before = E().stats().scenes;
  const std::string bytes = QuadScene().dump();
  int aborted = 0, loaded = 0;
  for (int round = 0; round < 20; ++round) {
    // The id the engine hands out is the one stats() lists that was not
    // there before (nothing else creates ids meanwhile).
    const std::set<std::string> before = ListedIds();
    std::string next;
    std::atomic<bool> stop{false};
    std::atomic<bool> unloaded{false};
    std::thread unloader([&] {
      while (!stop.load()) {
        for (const std::string& id : ListedIds()) {
          if (before.count(id) > 0) continue;
          const absl::Status s = E().UnloadScene(id);
          if (s.ok()) {
            next = id;
            unloaded = true;
            return;
          }
          ASSERT_EQ(s.code(), absl::StatusCode::kNotFound) << s;
        }
      }
    });
    auto load = std::async(std::launch::async,
                           [&] { return E().LoadScene(testing::SceneFromBytes(bytes)); });
    ASSERT_EQ(load.wait_for(seconds(60)), std::future_status::ready) << "LoadScene never finished";
    const absl::StatusOr<SceneInfo> info = load.get();
    // Give the unloader a moment to see the id, then stop it.
    for (int i = 0; i < 100 && !unloaded.load(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    stop = true;
    unloader.join();
    if (info.ok()) {
      ++loaded;
      if (unloaded) {
        EXPECT_EQ(info->id, next);
      } else {
        EXPECT_TRUE(E().UnloadScene(info->id).ok());
      }
    } else {
      ++aborted;
      EXPECT_EQ(info.status().code(), absl::StatusCode::kAborted) << info.status();
      EXPECT_NE(info.status().message().find("was unloaded while it loaded"), std::string::npos)
          << info.status();
      EXPECT_TRUE(unloaded.load());
    }
  }
  // Both outcomes are legitimate; which ones occur depends on timing (an
  // unload that wins the race is the case that used to leak).
  EXPECT_EQ(loaded + aborted, 20);
  RecordProperty("aborted_loads", aborted);
  EXPECT_EQ(E().stats().scenes, scenes_before);
  const QuadCopy third;
  EXPECT_EQ(E().stats().gl_object_bytes, bytes_two + scene_bytes)
      << "GPU copies of unloaded scenes remain (" << aborted << " loads lost the race)";
  ExpectRendersFinite(first.id(), "direct");
}

TEST(LoadUnloadRace, LoadRacingShutdownFinishes) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  const std::string bytes = QuadScene().dump();
  std::vector<std::future<absl::StatusOr<SceneInfo>>> loads;
  for (int i = 0; i < 4; ++i) {
    loads.push_back(std::async(
        std::launch::async, [&] { return (*engine)->LoadScene(testing::SceneFromBytes(bytes)); }));
  }
  (*engine)->Shutdown();
  for (auto& load : loads) {
    ASSERT_EQ(load.wait_for(seconds(60)), std::future_status::ready)
        << "LoadScene never finished after Shutdown";
    const absl::StatusOr<SceneInfo> info = load.get();
    if (!info.ok()) {
      EXPECT_EQ(info.status().code(), absl::StatusCode::kUnavailable) << info.status();
    }
  }
  EXPECT_EQ((*engine)->LoadScene(testing::SceneFromBytes(bytes)).status().code(),
            absl::StatusCode::kUnavailable);
}

}  // namespace load_unload_race_test
}  // namespace gistream::reliability
