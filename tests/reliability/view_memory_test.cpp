// Issue 13, finding 2 (unbounded memory), per-view state: what a solver
// allocates for each view it shades (pathtrace's accumulation, 24 bytes a
// pixel, and its image upload buffer, 16) is reserved from the server's
// memory budget before it is allocated (solvers/view_memory.h), refused
// with RESOURCE_EXHAUSTED naming it, and given back when the solver goes;
// a view's G-buffer, readback and encoder buffers are reserved again when a
// camera update resizes it.
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <thread>

#include "reliability/reliability_fixture.h"
#include "render/gbuffer.h"
#include "engine/frame_encoder.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace view_memory_test {

using namespace std::chrono_literals;

constexpr uint32_t kSmall = 16, kLarge = 256;

// Polls `pred` every 10 ms for at most 60 s (it waits on frames of a CPU
// path tracer and on jobs queued on the render thread, not on a timing).
template <typename Pred>
bool Eventually(Pred pred) {
  for (int i = 0; i < 6000 && !pred(); ++i) std::this_thread::sleep_for(10ms);
  return pred();
}

class RecordingSink final : public FrameSink {
 public:
  void OnFrame(std::shared_ptr<const EncodedFrame>) override { frames += 1; }
  void OnUpdateRejected(uint64_t, const absl::Status&) override {}
  void OnSessionFailed(const absl::Status& status) override {
    std::lock_guard lock(mutex);
    failure = status;
    failed = true;
  }
  std::atomic<int> frames{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;
  absl::Status failure;
};

std::unique_ptr<Engine> MakeEngine(uint64_t max_memory_bytes) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  options.max_memory_bytes = max_memory_bytes;
  auto engine = Engine::Create(options);
  EXPECT_TRUE(engine.ok()) << engine.status();  // GL tests never skip
  return engine.ok() ? *std::move(engine) : nullptr;
}

// What the engine holds for a session of pathtrace on the quad scene: after
// a kSmall^2 frame, then after a camera update resized it to kLarge^2 (the
// budget's bytes in use at each point; with `failure` set, the resized
// frame's failure instead).
struct Measured {
  uint64_t small = 0;
  uint64_t large = 0;
  absl::Status failure;
  bool renders_after = false;
};

Measured RunPathtraceSession(uint64_t max_memory_bytes) {
  Measured out;
  std::unique_ptr<Engine> engine = MakeEngine(max_memory_bytes);
  if (!engine) return out;
  Engine& e = *engine;
  auto scene = e.LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  EXPECT_TRUE(scene.ok()) << scene.status();
  if (!scene.ok()) return out;

  auto sink = std::make_shared<RecordingSink>();
  SessionConfig config;
  config.scene = scene->id;
  config.solver = "pathtrace";
  config.width = config.height = kSmall;
  config.pacing = Pacing::kOnRequest;
  config.encoding.format = ImageFormat::kPng;
  auto session = e.OpenSession(config, sink);
  EXPECT_TRUE(session.ok()) << session.status();
  if (!session.ok()) return out;
  EXPECT_TRUE(e.RequestFrames(session->id, 1).ok());
  EXPECT_TRUE(Eventually([&] { return sink->frames >= 1 || sink->failed; }));
  out.small = e.stats().memory_used_bytes;

  CameraUpdate resize;
  resize.width = kLarge;
  resize.height = kLarge;
  EXPECT_TRUE(e.PushUpdate(session->id, Update{1, resize}).ok());
  EXPECT_TRUE(e.RequestFrames(session->id, 1).ok());
  EXPECT_TRUE(Eventually([&] { return sink->frames >= 2 || sink->failed; }));
  out.large = e.stats().memory_used_bytes;
  {
    std::lock_guard lock(sink->mutex);
    out.failure = sink->failure;
  }
  e.CloseSession(session->id);

  // The engine stays up: a normal path-traced frame still renders.
  RenderRequest request;
  request.scene = scene->id;
  request.solver = "pathtrace";
  request.width = request.height = kSmall;
  request.encoding.format = ImageFormat::kPng;
  auto frame = e.Render(request);
  EXPECT_TRUE(frame.ok()) << frame.status();
  out.renders_after = frame.ok();

  // Unloading the scene drops its solver with every view's accumulation.
  EXPECT_TRUE(e.UnloadScene(scene->id).ok());
  EXPECT_TRUE(Eventually([&] { return e.stats().memory_used_bytes == 0; }))
      << e.stats().memory_used_bytes << " bytes still reserved";
  e.Shutdown();
  return out;
}

// Bytes a view of `side`^2 PNG frames holds in the engine (ReserveView).
uint64_t ViewBytes(uint32_t side) {
  return uint64_t(side) * side * GBuffer::kBytesPerPixel +
         EstimateFrameBytes(side, side, ImageFormat::kPng);
}

TEST(ViewMemory, PathtraceViewsAreReservedAndRefusedOverTheBudget) {
  const Measured fits = RunPathtraceSession(/*max_memory_bytes=*/0);
  ASSERT_TRUE(fits.failure.ok()) << fits.failure;
  ASSERT_GT(fits.small, 0u);
  // Resized: the view's buffers at the new size, the upload buffer grown to
  // it, and a second accumulation (the small view's stays, kMaxViews).
  const uint64_t large_pixels = uint64_t(kLarge) * kLarge;
  const uint64_t small_pixels = uint64_t(kSmall) * kSmall;
  EXPECT_EQ(fits.large - fits.small, ViewBytes(kLarge) - ViewBytes(kSmall) +
                                         16 * (large_pixels - small_pixels) + 24 * large_pixels);

  // One byte short of that: the large view's accumulation (the last thing
  // it reserves) is refused, naming it; nothing is left held.
  const Measured refused = RunPathtraceSession(fits.large - 1);
  EXPECT_STATUS(refused.failure, kResourceExhausted,
                "pathtrace: width x height 256x256 (its accumulation buffer) needs 1.5 MiB");
  EXPECT_STATUS(refused.failure, kResourceExhausted, "--max-memory-bytes");
  EXPECT_TRUE(refused.renders_after);
}

}  // namespace view_memory_test
}  // namespace gistream::reliability
