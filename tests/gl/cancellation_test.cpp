// Every long loop is cancellable (issue 30, util/cancellation.h): for every
// registered solver, a Render at its most expensive in-range parameters is
// cancelled once under way. The Render answers CANCELLED, the work stops
// (no dropped solver is kept waiting for its background job, which is
// asked to stop; a loop on the render thread ends at its next step), and
// the render thread answers the next request. Shutting an engine down
// while such a frame runs returns, too.
//
// The waits below are hang bounds (a minute, against the seconds a step
// takes here), not timing thresholds: the work they wait for would run for
// many minutes without the cancellation. The time each took is printed.
#include <atomic>
#include <chrono>
#include <future>
#include <map>
#include <thread>

#include <gtest/gtest.h>

#include "solvers/registry.h"
#include "support/frame_queue.h"
#include "support/render_helpers.h"

namespace gistream {
namespace cancellation_test {

using Clock = std::chrono::steady_clock;
using Params = std::map<std::string, std::string>;

// Each solver's most expensive parameters within their ranges that the
// Cornell box is not refused for before any work starts (the cases
// for antiradiance and implicit_visibility; bins_per_face 24, sh_probes'
// grid 16 of 16x16 faces, avg's 256^2 VPL maps and 256 area samples, and
// direct's 256 area samples of 256^2 faces, where more is refused for its
// memory or this GL's layer limit).
const std::map<std::string, Params>& ExtremeParams() {
  static const std::map<std::string, Params> table = {
      {"direct", {{"area_samples", "256"}, {"shadow_res", "256"}}},
      {"pathtrace", {{"spp", "4096"}, {"max_depth", "65536"}}},
      {"sh_probes", {{"grid", "16"}, {"face_size", "16"}, {"bounces", "64"}, {"tolerance", "0"}}},
      {"avg",
       {{"vpls", "2048"},
        {"bounces", "1024"},
        {"roulette", "false"},
        {"shadow_res", "256"},
        {"area_samples", "256"}}},
      {"implicit_visibility", {{"bins_per_face", "24"}, {"bounces", "4096"}, {"tolerance", "0"}}},
      {"antiradiance",
       {{"bins", "512"},
        {"iterations", "4096"},
        {"tolerance", "0"},
        {"scheme", "asymmetric"},
        {"antiradiance_steps", "64"}}},
  };
  return table;
}

double MsSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

TEST(Cancellation, EveryRegisteredSolverHasItsExtremeParametersHere) {
  for (const SolverDescription& d : AllSolverDescriptions()) {
    EXPECT_TRUE(ExtremeParams().contains(d.name))
        << d.name << ": add its most expensive parameters to ExtremeParams()";
  }
}

class CancelledRender : public ::testing::TestWithParam<std::string> {};

TEST_P(CancelledRender, StopsItsWorkAndFreesTheRenderThread) {
  const std::string solver = GetParam();
  Engine& engine = testing::SharedEngine();
  const testing::BundledCopy scene("cornell_box.gltf");
  RenderRequest request =
      testing::SolverRequest(scene.id(), solver, ExtremeParams().at(solver), 32);
  // The most samples a still view may take: on a fast GPU the rasterising
  // solvers' extreme parameters alone might finish before the cancel.
  request.refine_samples = 1024;
  // Cancelled after about 40 polls (20 ms apart): the work is under way.
  std::atomic<int> polls{0};
  Clock::time_point cancelled_at{};
  request.cancelled = [&] {
    if (++polls == 40) cancelled_at = Clock::now();
    return polls >= 40;
  };
  const auto frame = engine.Render(request);
  ASSERT_EQ(frame.status().code(), absl::StatusCode::kCancelled)
      << solver << ": " << (frame.ok() ? "finished before the cancel" : frame.status().ToString());
  // The render thread is free: a small frame comes back (after the closed
  // session's release, which drops the solver nobody uses any more).
  const RenderRequest small = testing::SolverRequest(scene.id(), "direct", {}, 8);
  const auto next = engine.Render(small);
  ASSERT_TRUE(next.ok()) << next.status();
  const double next_ms = MsSince(cancelled_at);
  // No background job runs on: asked to stop, each ends within a step.
  // (Small frames refresh the engine's figures.)
  for (int i = 0;
       i < 600 && (engine.stats().background_jobs > 0 || engine.stats().retiring_solvers > 0);
       ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ASSERT_TRUE(engine.Render(small).ok());
  }
  EXPECT_EQ(engine.stats().background_jobs, 0u) << solver << ": its background job goes on";
  EXPECT_EQ(engine.stats().retiring_solvers, 0u);
  std::printf("%s: the next Render %.0f ms after the cancel, no background job after %.0f ms\n",
              solver.c_str(), next_ms, MsSince(cancelled_at));
  EXPECT_EQ(engine.stats().sessions, 0u);
}

INSTANTIATE_TEST_SUITE_P(EverySolver, CancelledRender, ::testing::ValuesIn([] {
                           std::vector<std::string> names;
                           for (const SolverDescription& d : AllSolverDescriptions()) {
                             names.push_back(d.name);
                           }
                           return names;
                         }()),
                         [](const auto& p) { return p.param; });

// Shutdown asks every frame in progress to stop: an engine whose render
// thread is inside implicit_visibility's 4096 bounces, with antiradiance's
// 4096-iteration job on the pool, shuts down within a step of each.
TEST(Cancellation, ShutdownStopsTheFrameInProgressAndTheJobs) {
  EngineOptions options;
  options.scene_dir = std::string(GISTREAM_SOURCE_DIR "/scenes");
  auto created = Engine::Create(options);
  ASSERT_TRUE(created.ok()) << created.status();
  std::unique_ptr<Engine> engine = std::move(created).value();
  auto scene = engine->LoadScene(testing::SceneByName("cornell_box.gltf"));
  ASSERT_TRUE(scene.ok()) << scene.status();
  std::vector<std::shared_ptr<testing::FrameQueue>> sinks;
  for (const char* solver : {"antiradiance", "implicit_visibility"}) {
    auto sink = std::make_shared<testing::FrameQueue>();
    auto opened = engine->OpenSession(
        testing::ExrStreamConfig(scene->id, solver, ExtremeParams().at(solver), 32), sink);
    ASSERT_TRUE(opened.ok()) << opened.status();
    sinks.push_back(sink);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // under way
  const auto start = Clock::now();
  // Shutdown and destruction (which joins the render thread and waits for
  // the solvers' jobs) on a thread of their own, so a hang is a failure.
  auto done = std::make_shared<std::promise<void>>();
  std::future<void> finished = done->get_future();
  std::thread([engine = std::move(engine), done]() mutable {
    engine->Shutdown();
    engine.reset();
    done->set_value();
  }).detach();
  if (finished.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
    ADD_FAILURE() << "the engine did not shut down within a minute";
    std::abort();  // its threads still run what nobody stopped
  }
  std::printf("shut down in %.0f ms\n", MsSince(start));
}

}  // namespace cancellation_test
}  // namespace gistream
