// `avg`'s voxelize and trace run as a background job on the CPU pool
// (issue 12), the first solve's too. With the pool's workers held busy, the Update of a moved
// node returns without having run either stage: UpdateComplete is false,
// the frame reports both skipped and the shown VPLs are the last ones.
// Once the job is taken the VPLs equal a synchronous full voxelization and
// trace of the moved scene bitwise; a move while the job runs is traced by
// one more job, with the newest transforms. Through the engine, a stream's
// frames say which scene version their GI reflects while the job runs, and
// the settled frame equals a fresh solve of the moved scene. A still
// view's second set of VPLs (`still_vpls`) is one more job once nothing is
// due, joined to the shown VPLs; a move cancels it.
#include <chrono>
#include <future>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "gl/stage_timer.h"
#include "scene/gltf/gltf_import.h"
#include "scene/gpu/gpu_scene.h"
#include "solvers/avg/avg_solver.h"
#include "support/frame_queue.h"
#include "support/gl_context.h"
#include "support/held_pool.h"
#include "support/render_helpers.h"
#include "util/cpu_pool.h"

namespace gistream {
namespace avg_background_trace_test {

constexpr int kVpls = 256, kGrid = 32;
// No still view's second set but in the test of it (StillViewsSecondSet).
const std::map<std::string, std::string> kParams = {
    {"vpls", std::to_string(kVpls)}, {"still_vpls", "0"},
    {"grid", std::to_string(kGrid)}, {"shadow_res", "16"},
    {"area_samples", "4"},           {"direct_shadow_res", "32"}};

// The tall block (node 6) moved inside the walls: the grid keeps its place,
// so the job voxelizes the moved box only.
NodeTransformUpdate MoveTallBlock(const glm::vec3& translation) {
  NodeTransformUpdate move;
  move.node = 6;
  move.translation = translation;
  return move;
}

using testing::HeldPool;

class AvgBackgroundTrace : public testing::GlContextTest {
 protected:
  void SetUp() override {
    testing::GlContextTest::SetUp();
    auto scene = ImportSceneByName(std::string(GISTREAM_SOURCE_DIR "/scenes"), "cornell_box", {});
    ASSERT_TRUE(scene.ok()) << scene.status();
    state_ = std::make_unique<SceneState>(std::make_shared<const Scene>(*std::move(scene)));
    auto gpu = GpuScene::Upload(*state_);
    ASSERT_TRUE(gpu.ok()) << gpu.status();
    gpu_ = *std::move(gpu);
    solver_ = CreateSolver();
    // The first solve is a background job too: frames (Updates) go on
    // until it is taken and its maps are drawn.
    Update(kChangeAll);
    while (!solver_->UpdateComplete()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      Update(kChangeNone);
    }
  }

  static std::unique_ptr<AvgSolver> CreateSolver(
      const std::map<std::string, std::string>& more = {}) {
    std::map<std::string, std::string> values = kParams;
    for (const auto& [k, v] : more) values[k] = v;
    auto params = ValidateParams(AvgSolver::Describe(), values);
    EXPECT_TRUE(params.ok()) << params.status();
    auto solver = AvgSolver::Create(*params);
    EXPECT_TRUE(solver.ok()) << solver.status();
    return std::unique_ptr<AvgSolver>(static_cast<AvgSolver*>(solver->release()));
  }

  // One frame's Update (no budget: a re-map is drawn whole); its stage
  // timings in timings_.
  void Update(ChangeMask changes) {
    gl::StageTimer timer;
    SolverContext ctx{*state_, *gpu_, timer};
    const absl::Status status = solver_->Update(ctx, changes);
    EXPECT_TRUE(status.ok()) << status;
    timings_ = timer.Finish();
  }
  bool Ran(const std::string& stage) const {
    for (const StageTiming& t : timings_) {
      if (t.name == stage) return !t.skipped;
    }
    ADD_FAILURE() << "stage " << stage << " not reported";
    return false;
  }
  double Stat(const std::string& name) const {
    for (const auto& [k, v] : solver_->Stats()) {
      if (k == name) return v;
    }
    ADD_FAILURE() << "stat " << name << " not reported";
    return -1.0;
  }
  ChangeMask Move(const glm::vec3& translation) {
    return state_->Apply(MoveTallBlock(translation));
  }
  // Frames until the background work is taken and drawn; returns how many
  // of them ran trace_vpls. Polled as the engine polls a Render.
  int UpdateUntilComplete() {
    int traces = 0;
    while (!solver_->UpdateComplete()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      Update(kChangeNone);
      if (Ran("trace_vpls")) {
        ++traces;
        EXPECT_TRUE(Ran("voxelize"));  // the job's stages reported in the frame that takes it
      }
    }
    return traces;
  }
  // The VPLs equal a synchronous full voxelization and trace of the scene
  // as it is now, bitwise.
  // With `joined`, joined with a second set of as many paths going on with
  // the sequence (a still view's VPLs).
  void ExpectFullTrace(bool joined = false) const {
    const avg::VoxelGrid grid = avg::VoxelGrid::Build(*state_, kGrid);
    const glm::vec3 center = grid.origin() + 0.5f * grid.extent();
    const auto lights = avg::CollectVplLights(*state_, center, 0.5f * glm::length(grid.extent()));
    avg::VplTraceSettings settings;
    settings.vpls = kVpls;
    avg::VplTraceResult full = avg::TraceVpls(grid, lights, settings);
    if (joined) {
      avg::VplTraceSettings second = settings;
      second.sample_offset = full.paths;
      full = avg::JoinTraces(full, avg::TraceVpls(grid, lights, second));
    }
    const avg::VplTraceResult& shown = solver_->vpls();
    EXPECT_EQ(shown.paths, full.paths);
    EXPECT_EQ(shown.path_first, full.path_first);
    ExpectSameVpls(shown.vpls, full.vpls);
  }
  static void ExpectSameVpls(const std::vector<avg::Vpl>& a, const std::vector<avg::Vpl>& b) {
    ASSERT_EQ(a.size(), b.size());
    ASSERT_GT(a.size(), 1u);
    for (size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].position, b[i].position) << i;
      ASSERT_EQ(a[i].normal, b[i].normal) << i;
      ASSERT_EQ(a[i].flux, b[i].flux) << i;
      ASSERT_EQ(a[i].bounce, b[i].bounce) << i;
    }
  }

  std::unique_ptr<SceneState> state_;
  std::unique_ptr<GpuScene> gpu_;
  std::unique_ptr<AvgSolver> solver_;
  std::vector<StageTiming> timings_;
};

TEST_F(AvgBackgroundTrace, AMoveReturnsBeforeTheTraceAndEndsAsAFullTrace) {
  const std::vector<avg::Vpl> before = solver_->vpls().vpls;
  const ChangeMask changes = Move({-0.05f, 0.0f, 0.05f});
  {
    HeldPool held;
    Update(changes);
    // The job cannot have run: this Update did not wait for it.
    EXPECT_FALSE(solver_->UpdateComplete());
    EXPECT_FALSE(Ran("voxelize"));
    EXPECT_FALSE(Ran("trace_vpls"));
    EXPECT_EQ(Stat("trace_pending"), 1.0);
    EXPECT_EQ(Stat("gi_versions_behind"), 1.0);
    // Frames shade the last VPLs and their maps.
    ExpectSameVpls(solver_->vpls().vpls, before);
    EXPECT_EQ(Stat("vpl_maps_pending"), 0.0);
    Update(kChangeNone);  // a frame while the job waits changes none of it
    EXPECT_FALSE(solver_->UpdateComplete());
    EXPECT_FALSE(Ran("trace_vpls"));
    ExpectSameVpls(solver_->vpls().vpls, before);
  }
  EXPECT_EQ(UpdateUntilComplete(), 1);
  EXPECT_EQ(Stat("voxelize_partial"), 1.0);
  EXPECT_GT(Stat("vpl_paths_kept"), 0.0);
  EXPECT_EQ(Stat("trace_pending"), 0.0);
  EXPECT_EQ(Stat("gi_versions_behind"), 0.0);
  ExpectFullTrace();
}

TEST_F(AvgBackgroundTrace, TheFirstSolveReturnsBeforeItsJobAndEndsAsAFullTrace) {
  // A new solver: its first Update starts the job and returns (the render
  // thread never waits for the pool); frames meanwhile have no VPLs.
  solver_ = CreateSolver();
  {
    HeldPool held;
    Update(kChangeAll);
    EXPECT_FALSE(solver_->UpdateComplete());
    EXPECT_FALSE(Ran("voxelize"));
    EXPECT_FALSE(Ran("trace_vpls"));
    EXPECT_EQ(Stat("trace_pending"), 1.0);
    EXPECT_TRUE(solver_->vpls().vpls.empty());
    Update(kChangeNone);
    EXPECT_FALSE(solver_->UpdateComplete());
  }
  EXPECT_EQ(UpdateUntilComplete(), 1);
  EXPECT_EQ(Stat("trace_pending"), 0.0);
  ExpectFullTrace();
}

TEST_F(AvgBackgroundTrace, AMoveWhileTheJobRunsIsTracedByTheNextJob) {
  // (A pool of one thread ran the first job inline: the second Update takes it.)
  const bool held_workers = HeldPool::Holds();
  {
    HeldPool held;
    Update(Move({-0.05f, 0.0f, 0.05f}));
    EXPECT_FALSE(solver_->UpdateComplete());
    // The running job has the first move's snapshot; the second is due.
    Update(Move({0.03f, 0.0f, -0.02f}));
    EXPECT_FALSE(solver_->UpdateComplete());
    if (held_workers) {
      EXPECT_FALSE(Ran("trace_vpls"));
      EXPECT_EQ(Stat("gi_versions_behind"), 2.0);
    }
  }
  // The first job is taken, the second started with the newest transforms
  // in the same frame, then taken too.
  EXPECT_EQ(UpdateUntilComplete(), held_workers ? 2 : 1);
  EXPECT_EQ(Stat("gi_versions_behind"), 0.0);
  ExpectFullTrace();
}

TEST_F(AvgBackgroundTrace, AStillViewJoinsASecondSetAndAMoveCancelsIt) {
  solver_ = CreateSolver({{"still_vpls", std::to_string(2 * kVpls)}});
  // The first solve, then the second set: complete only once both are in.
  Update(kChangeAll);
  bool showed_first_set_alone = false;
  while (!solver_->UpdateComplete()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    Update(kChangeNone);
    showed_first_set_alone |= Stat("still_pending") == 1.0 && !solver_->vpls().vpls.empty();
  }
  EXPECT_TRUE(showed_first_set_alone);
  EXPECT_EQ(Stat("still_pending"), 0.0);
  EXPECT_GT(Stat("still_vpls"), 0.0);
  ExpectFullTrace(/*joined=*/true);
  // The first set's maps were copied, only the second set's drawn.
  EXPECT_EQ(Stat("vpl_maps_kept") + Stat("still_vpls"), Stat("vpls"));

  if (!HeldPool::Holds()) return;  // a one-thread pool runs each job inline
  // A move: the next trace is of `vpls` alone; hold the pool once its job
  // is done, so that the frame taking it starts the second set, which the
  // next move cancels before it runs.
  Update(Move({-0.05f, 0.0f, 0.05f}));
  while (solver_->BackgroundBusy()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  {
    HeldPool held;
    Update(kChangeNone);
    EXPECT_EQ(Stat("still_vpls"), 0.0);
    EXPECT_EQ(Stat("still_pending"), 1.0);
    EXPECT_FALSE(solver_->UpdateComplete());
    Update(Move({0.03f, 0.0f, -0.02f}));
    EXPECT_EQ(Stat("still_vpls"), 0.0);
  }
  while (!solver_->UpdateComplete()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    Update(kChangeNone);
  }
  // The second set of the newest transforms, not of the cancelled job's.
  EXPECT_GT(Stat("still_vpls"), 0.0);
  ExpectFullTrace(/*joined=*/true);
}

}  // namespace avg_background_trace_test
}  // namespace gistream

namespace gistream {
namespace avg_background_trace_test {

using testing::FrameStat;

TEST(AvgBackgroundTraceStream, FramesSayWhatTheirGiReflectsAndSettleOnAFreshSolve) {
  const testing::BundledCopy scene("cornell_box.gltf"), fresh_scene("cornell_box.gltf");
  SessionConfig config = testing::ExrStreamConfig(scene.id(), "avg", kParams, 24);
  auto sink = std::make_shared<testing::FrameQueue>();
  auto opened = testing::SharedEngine().OpenSession(config, sink);
  ASSERT_TRUE(opened.ok()) << opened.status();
  ASSERT_NE(
      sink->WaitFor([](const EncodedFrame& f) { return FrameStat(f, "update_complete") == 1.0; }),
      nullptr);
  const NodeTransformUpdate move = MoveTallBlock({-0.05f, 0.0f, 0.05f});
  ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, {1, move}).ok());
  auto done = sink->WaitFor([](const EncodedFrame& f) {
    return f.last_update_seq >= 1 && FrameStat(f, "update_complete") == 1.0;
  });
  testing::SharedEngine().CloseSession(opened->id);
  ASSERT_NE(done, nullptr);
  EXPECT_EQ(FrameStat(*done, "trace_pending"), 0.0);
  EXPECT_EQ(FrameStat(*done, "gi_versions_behind"), 0.0);
  // Every frame that showed the move while its trace was pending said the
  // GI was behind.
  EXPECT_EQ(sink->Count([](const EncodedFrame& f) {
    return f.last_update_seq >= 1 && FrameStat(f, "trace_pending") == 1.0 &&
           FrameStat(f, "gi_versions_behind") < 1.0;
  }),
            0u);
  // Same VPLs (bitwise, above), each map drawn or copied from the same
  // geometry: the fresh solve's image to float rounding (relative 1e-4).
  testing::ExpectSameImage(testing::DecodeExr(*done),
                           testing::RenderRequestExr(testing::SolverRequest(
                               fresh_scene.id(), "avg", kParams, 24, {{1, move}})));
}

}  // namespace avg_background_trace_test
}  // namespace gistream
