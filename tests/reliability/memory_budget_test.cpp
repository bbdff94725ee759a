// Issue 13, finding 2 (unbounded memory): every solver's memory is
// estimated from its parameters and the scene before it is built, through
// one path (solvers/memory_estimate.h, EstimateSolverMemory), and reserved
// from one server-wide budget (util/memory_budget.h, --max-memory-bytes)
// that scenes (decoded images included) and G-buffers share; unloading a
// scene or closing a session gives its bytes back.
#include <gtest/gtest.h>

#include <absl/strings/escaping.h>

#include <functional>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include "encode/encode.h"
#include "reliability/reliability_fixture.h"
#include "render/gbuffer.h"
#include "service/test_server.h"
#include "solvers/registry.h"
#include "support/frame_queue.h"
#include "support/render_helpers.h"
#include "util/memory_budget.h"

namespace gistream::reliability {
namespace memory_budget_test {

using namespace std::chrono_literals;

// Polls `pred` every 10 ms for at most 10 s (what it waits on is a job
// queued on the render thread, not a timing property).
template <typename Pred>
bool Eventually(Pred pred) {
  for (int i = 0; i < 1000 && !pred(); ++i) std::this_thread::sleep_for(10ms);
  return pred();
}

class NullSink final : public FrameSink {
 public:
  void OnFrame(std::shared_ptr<const EncodedFrame>) override { frames += 1; }
  void OnUpdateRejected(uint64_t, const absl::Status&) override {}
  void OnSessionFailed(const absl::Status&) override {}
  std::atomic<int> frames{0};
};

TEST(MemoryBudget, ReservationsAddUpAndComeBack) {
  MemoryBudget budget(1000);
  EXPECT_EQ(budget.limit(), 1000u);
  auto a = budget.Reserve(600, "a");
  ASSERT_TRUE(a.ok()) << a.status();
  EXPECT_EQ(budget.used(), 600u);
  EXPECT_STATUS(StatusOf(budget.Reserve(401, "params.x=3")), kResourceExhausted,
                "params.x=3 needs 401 B, more than the 400 B left of the server's memory budget "
                "(--max-memory-bytes 1000 B, 600 B in use)");
  {
    auto b = budget.Reserve(400, "b");
    ASSERT_TRUE(b.ok());
    EXPECT_EQ(budget.used(), 1000u);
    MemoryBudget::Reservation moved = std::move(*b);
    EXPECT_EQ(moved.bytes(), 400u);
    EXPECT_EQ(budget.used(), 1000u);  // a move holds the same bytes once
  }
  EXPECT_EQ(budget.used(), 600u);
  a->Release();
  EXPECT_EQ(budget.used(), 0u);
  EXPECT_GT(DefaultMemoryLimit(), 0u);
  EXPECT_EQ(FormatBytes(5ull << 30), "5.0 GiB");
}

// The shared engine refuses tiny antiradiance patches from the estimate:
// 4 triangles x 4^12 leaves need hundreds of GiB of tables, and nothing is
// split or allocated first.
TEST(MemoryBudget, TinyAntiradiancePatchSizeIsRefusedByItsEstimate) {
  const QuadCopy scene;
  const bool can_measure = ResetPeakRss();
  const uint64_t before = StatusKiB("VmRSS");
  const uint64_t used = E().stats().memory_used_bytes;
  auto frame = E().Render(Request(scene.id(), "antiradiance", {},
                                  {{"elements", "triangles"}, {"patch_size", "0.000001"}}));
  EXPECT_STATUS(StatusOf(frame), kResourceExhausted,
                "antiradiance: patch_size=1e-06 bins=128 (largest part: links of ");
  EXPECT_STATUS(StatusOf(frame), kResourceExhausted, "of the server's memory budget");
  if (can_measure) {
    // 256 MiB: the engine's own working set varies; the tables would be 400 GiB.
    EXPECT_LT(StatusKiB("VmHWM"), before + 256 * 1024) << "peak RSS grew while refusing";
  }
  EXPECT_TRUE(Eventually([&] { return E().stats().memory_used_bytes == used; }))
      << "a refused solver holds no reservation";
  ExpectRendersFinite(scene.id(), "direct");
}

// Every registered solver has an estimate, and the defaults on a small
// scene fit in a few hundred MiB (a refusal of a normal request would be a
// bug in an estimate).
TEST(MemoryBudget, EverySolverEstimatesItsDefaults) {
  const QuadCopy scene;
  for (const SolverDescription& d : AllSolverDescriptions()) {
    auto frame = E().Render(Request(scene.id(), d.name));
    EXPECT_TRUE(frame.ok()) << d.name << ": " << frame.status();
  }
  const EngineStats stats = E().stats();
  EXPECT_GT(stats.memory_used_bytes, 0u);
  EXPECT_LE(stats.memory_used_bytes, stats.memory_limit_bytes);
}

// A session of `solver` with `params` on its own engine's Cornell box at
// 16 x 16, until a frame satisfies `done`: that frame and the session's
// reservation less its view's (G-buffer and encoder buffers, at most 200
// bytes a pixel).
struct Reserved {
  std::shared_ptr<const EncodedFrame> frame;
  double bytes = 0.0;
};
Reserved SessionReservation(const std::string& solver, std::map<std::string, std::string> params,
                            const std::function<bool(const EncodedFrame&)>& done) {
  EngineOptions options;
  options.scene_dir = std::filesystem::path(GISTREAM_SOURCE_DIR) / "scenes";
  auto engine = Engine::Create(options);
  EXPECT_TRUE(engine.ok()) << engine.status();
  if (!engine.ok()) return {};
  Engine& e = **engine;
  Reserved out;
  auto info = e.LoadScene(testing::SceneByName("cornell_box.gltf"));
  EXPECT_TRUE(info.ok()) << info.status();
  if (info.ok()) {
    const uint64_t with_scene = e.stats().memory_used_bytes;
    auto sink = std::make_shared<testing::FrameQueue>();
    SessionConfig config;
    config.scene = info->id;
    config.solver = solver;
    config.params = std::move(params);
    config.width = config.height = 16;
    config.encoding.format = ImageFormat::kPng;
    auto session = e.OpenSession(config, sink);
    EXPECT_TRUE(session.ok()) << session.status();
    if (session.ok()) {
      out.frame = sink->WaitFor(done);
      out.bytes = double(e.stats().memory_used_bytes - with_scene) - 16.0 * 16.0 * 200.0;
      e.CloseSession(session->id);
    }
  }
  e.Shutdown();
  return out;
}

// antiradiance's estimate against what it builds (issue 30: the links
// were estimated 30 times low): a session's reservation, less its view's,
// covers the tables and both copies of the links that its stats report,
// and is not more than twice them.
TEST(MemoryBudget, AntiradianceEstimateCoversWhatItBuilds) {
  const Reserved r = SessionReservation(
      "antiradiance", {{"elements", "triangles"}, {"patch_size", "0.05"}, {"bins", "256"}},
      [](const EncodedFrame& f) {
        return testing::FrameStat(f, "links_pending") == 0.0 &&
               testing::FrameStat(f, "link_bytes") > 0;
      });
  ASSERT_TRUE(r.frame);
  const double built = testing::FrameStat(*r.frame, "table_bytes") +
                       2.0 * testing::FrameStat(*r.frame, "link_bytes") +
                       testing::FrameStat(*r.frame, "shadow_map_bytes");
  RecordProperty("reserved_bytes", std::to_string(r.bytes));
  RecordProperty("built_bytes", std::to_string(built));
  EXPECT_GE(r.bytes, built) << "estimate below what the solver built";
  EXPECT_LE(r.bytes, 2.0 * built) << "estimate more than twice what the solver built";
}

// Every solver's estimate at its defaults against what it built (issue 30,
// item 2): a session's reservation, less its view's, covers the bytes its
// frame's stats report (every `*_bytes` stat but the scene's; antiradiance
// keeps its links twice, per pair of roots and sorted), and is not more
// than three times them (plus 1 MiB). On the Cornell box at 16 x 16, once
// the solution is complete. Measured reserved / built: direct 2.00
// (shadow maps), sh_probes 1.56, avg 1.86, implicit_visibility 2.11,
// antiradiance 1.76; pathtrace reports no bytes (its BVH is not a stat),
// so only its 1 MiB bound holds it (0.84 MiB reserved).
class EveryEstimate : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryEstimate, CoversWhatItsSolverBuilt) {
  const std::string solver = GetParam();
  const Reserved r = SessionReservation(solver, {}, [](const EncodedFrame& f) {
    for (const auto& [name, value] : f.stats) {
      if (name == "update_complete" && value != 1.0) return false;
    }
    return true;
  });
  ASSERT_TRUE(r.frame);
  double built = 0.0;
  for (const auto& [name, value] : r.frame->stats) {
    if (name.size() > 6 && name.ends_with("_bytes") && name != "scene_gpu_bytes") built += value;
    if (solver == "antiradiance" && name == "link_bytes") built += value;
  }
  RecordProperty("reserved_bytes", std::to_string(r.bytes));
  RecordProperty("built_bytes", std::to_string(built));
  EXPECT_GE(r.bytes, built) << solver << ": estimate below what the solver built";
  EXPECT_LE(r.bytes, 3.0 * built + (1 << 20)) << solver << ": estimate far above what it built";
}

INSTANTIATE_TEST_SUITE_P(Solvers, EveryEstimate, ::testing::ValuesIn([] {
                           std::vector<std::string> names;
                           for (const SolverDescription& d : AllSolverDescriptions())
                             names.push_back(d.name);
                           return names;
                         }()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(MemoryBudget, UnloadAndCloseReturnTheBudgetToItsBaseline) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  Engine& e = **engine;
  EXPECT_EQ(e.stats().memory_limit_bytes, DefaultMemoryLimit());
  const uint64_t baseline = e.stats().memory_used_bytes;
  EXPECT_EQ(baseline, 0u);

  auto info = e.LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  ASSERT_TRUE(info.ok()) << info.status();
  const uint64_t with_scene = e.stats().memory_used_bytes;
  EXPECT_GT(with_scene, baseline);

  // A session: its view's G-buffer (64 x 64) and its solver.
  auto sink = std::make_shared<NullSink>();
  SessionConfig config;
  config.scene = info->id;
  config.solver = "sh_probes";
  config.width = 64;
  config.height = 64;
  config.encoding.format = ImageFormat::kPng;
  auto session = e.OpenSession(config, sink);
  ASSERT_TRUE(session.ok()) << session.status();
  ASSERT_TRUE(Eventually([&] { return sink->frames > 0; }));
  const uint64_t with_session = e.stats().memory_used_bytes;
  EXPECT_GE(with_session, with_scene + 64 * 64 * GBuffer::kBytesPerPixel);

  e.CloseSession(session->id);
  ASSERT_TRUE(e.UnloadScene(info->id).ok());
  EXPECT_TRUE(Eventually([&] { return e.stats().memory_used_bytes == baseline; }))
      << e.stats().memory_used_bytes << " bytes still reserved";
  e.Shutdown();
}

TEST(MemoryBudget, ASceneOverTheBudgetIsRefusedAndHoldsNothing) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  options.max_memory_bytes = 8 << 20;
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  auto textured = [](int side) {
    auto png = EncodePng(std::vector<uint8_t>(size_t(side) * side * 4, 200), side, side);
    EXPECT_TRUE(png.ok()) << png.status();
    nlohmann::json doc = QuadScene();
    doc["images"] = {{{"uri", "data:image/png;base64," + absl::Base64Escape(*png)}}};
    doc["textures"] = {{{"source", 0}}};
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    return testing::SceneFromBytes(doc.dump());
  };
  // A 2048 x 2048 texture decodes to 16 MiB: refused from its header by the
  // import (scene/gltf/import_memory.h), before a pixel is decoded.
  EXPECT_STATUS(StatusOf((*engine)->LoadScene(textured(2048))), kResourceExhausted,
                "images[0]: 2048x2048 decoded pixels needs 16.0 MiB");
  EXPECT_EQ((*engine)->stats().memory_used_bytes, 0u);
  // 1024 x 1024 decodes (4 MiB), but with its GPU copy (5.3 MiB with mips)
  // the scene does not fit.
  EXPECT_STATUS(StatusOf((*engine)->LoadScene(textured(1024))), kResourceExhausted,
                "scene: its geometry and images (");
  EXPECT_EQ((*engine)->stats().memory_used_bytes, 0u);
  // A solver whose estimate exceeds what is left: avg's atlases at 2048
  // VPLs of 256^2 are 1 GiB.
  auto info = (*engine)->LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  ASSERT_TRUE(info.ok()) << info.status();
  EXPECT_STATUS(StatusOf((*engine)->Render(
                    Request(info->id, "avg", {}, {{"vpls", "2048"}, {"shadow_res", "256"}}))),
                kResourceExhausted,
                "avg: vpls=2048 still_vpls=2048 shadow_res=256 (largest part: two atlases");
  auto frame = (*engine)->Render(
      Request(info->id, "direct", {}, {{"area_samples", "4"}, {"shadow_res", "64"}}));
  ASSERT_TRUE(frame.ok()) << frame.status();
  EXPECT_EQ(testing::DecodeExr(*frame).non_finite(), 0u);
  (*engine)->Shutdown();
}

TEST(MemoryBudget, GetServerStatusReportsTheBudget) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  options.max_memory_bytes = 3ull << 30;
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  auto info = (*engine)->LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  ASSERT_TRUE(info.ok()) << info.status();
  testing::TestServer server(**engine);
  grpc::ClientContext context;
  testing::SetDeadline(&context);
  testing::pb::ServerStatus status;
  ASSERT_TRUE(server.stub().GetServerStatus(&context, {}, &status).ok());
  EXPECT_EQ(status.memory_budget_limit_bytes(), 3ull << 30);
  EXPECT_EQ(status.memory_budget_used_bytes(), (*engine)->stats().memory_used_bytes);
  EXPECT_GT(status.memory_budget_used_bytes(), 0u);
}

}  // namespace memory_budget_test
}  // namespace gistream::reliability
