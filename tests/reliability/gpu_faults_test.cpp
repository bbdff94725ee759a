// Issue 13, finding 6 (GPU faults half handled): after a context reset,
// health stayed SERVING, new sessions were accepted, Render waited forever
// and shutdown hung. Now a reset fails every session and pending Render
// with UNAVAILABLE, turns health NOT_SERVING, recreates the context and
// re-uploads every scene from its CPU state (health SERVING again), or
// exits with status 70 when it cannot; GL_OUT_OF_MEMORY on an allocation
// is RESOURCE_EXHAUSTED with nothing kept. llvmpipe produces neither
// fault, so both are injected (gl/fault_injection.h: files in
// EngineOptions::test_fault_dir).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>
#include <thread>
#include <vector>

#include "reliability/reliability_fixture.h"
#include "service/test_server.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace gpu_faults_test {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// A fault directory of its own, removed at the end.
class FaultDir {
 public:
  FaultDir() {
    path_ = fs::temp_directory_path() /
            ("gistream-faults-" + std::to_string(::getpid()) + "-" + std::to_string(next_++));
    fs::create_directories(path_);
  }
  ~FaultDir() {
    std::error_code error;
    fs::remove_all(path_, error);
  }
  const fs::path& path() const { return path_; }
  void Trigger(const std::string& fault) const { std::ofstream(path_ / fault) << "1"; }
  bool Pending(const std::string& fault) const { return fs::exists(path_ / fault); }

 private:
  fs::path path_;
  static inline int next_ = 0;
};

class RecordingSink final : public FrameSink {
 public:
  void OnFrame(std::shared_ptr<const EncodedFrame>) override { frames += 1; }
  void OnUpdateRejected(uint64_t, const absl::Status&) override {}
  void OnSessionFailed(const absl::Status& status) override {
    std::lock_guard lock(mutex);
    failures.push_back(status);
  }
  std::atomic<int> frames{0};
  std::mutex mutex;
  std::vector<absl::Status> failures;
};

std::unique_ptr<Engine> FaultyEngine(const FaultDir& faults) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  options.test_fault_dir = faults.path();
  auto engine = Engine::Create(options);
  EXPECT_TRUE(engine.ok()) << engine.status();
  return engine.ok() ? *std::move(engine) : nullptr;
}

template <typename Pred>
bool Eventually(Pred pred) {
  for (int i = 0; i < 2000 && !pred(); ++i) std::this_thread::sleep_for(10ms);
  return pred();
}

TEST(GpuFaults, ResetFailsEverythingInFlightThenRecoversWithTheScenes) {
  const FaultDir faults;
  auto engine = FaultyEngine(faults);
  ASSERT_NE(engine, nullptr);
  std::mutex events_mutex;
  std::vector<bool> serving_events;
  engine->SetServingListener([&](bool serving) {
    std::lock_guard lock(events_mutex);
    serving_events.push_back(serving);
  });
  auto info = engine->LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  ASSERT_TRUE(info.ok()) << info.status();
  auto before = engine->Render(Request(info->id, "direct"));
  ASSERT_TRUE(before.ok()) << before.status();

  // A continuous session with frames, and a Render that takes many slices
  // (4096 samples per pixel of 64 x 64 at 1 ms a slice).
  auto sink = std::make_shared<RecordingSink>();
  SessionConfig config;
  config.scene = info->id;
  config.width = 16;
  config.height = 16;
  auto session = engine->OpenSession(config, sink);
  ASSERT_TRUE(session.ok()) << session.status();
  ASSERT_TRUE(Eventually([&] { return sink->frames > 0; }));
  RenderRequest slow = Request(info->id, "pathtrace", {}, {{"spp", "4096"}});
  slow.width = slow.height = 64;
  slow.frame_budget_ms = 1.0;
  auto pending = std::async(std::launch::async, [&] { return engine->Render(slow); });
  ASSERT_EQ(pending.wait_for(200ms), std::future_status::timeout) << "the slow render was not slow";

  faults.Trigger("gpu_reset");
  const absl::StatusOr<EncodedFrame> failed = pending.get();
  EXPECT_STATUS(StatusOf(failed), kUnavailable, "GPU reset: the render context was lost");
  ASSERT_TRUE(Eventually([&] {
    std::lock_guard lock(sink->mutex);
    return !sink->failures.empty();
  }));
  {
    std::lock_guard lock(sink->mutex);
    EXPECT_STATUS(sink->failures.front(), kUnavailable, "GPU reset");
  }
  EXPECT_FALSE(faults.Pending("gpu_reset"));
  // Calls made during the recovery are UNAVAILABLE too; it ends with
  // health SERVING again.
  EXPECT_TRUE(Eventually([&] {
    std::lock_guard lock(events_mutex);
    return serving_events.size() >= 2;
  }));
  {
    std::lock_guard lock(events_mutex);
    EXPECT_EQ(serving_events, (std::vector<bool>{false, true}));
  }
  engine->CloseSession(session->id);

  // The scene came back from its CPU copy: the same frame as before.
  auto after = engine->Render(Request(info->id, "direct"));
  ASSERT_TRUE(after.ok()) << after.status();
  const testing::FloatImage a = testing::DecodeExr(*before);
  const testing::FloatImage b = testing::DecodeExr(*after);
  EXPECT_EQ(b.non_finite(), 0u);
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  for (size_t i = 0; i < a.rgba.size(); ++i) {
    ASSERT_NEAR(a.rgba[i], b.rgba[i], 1e-6f) << "value " << i;
  }
  // New sessions work, and shutdown does not hang.
  auto again = engine->OpenSession(config, std::make_shared<RecordingSink>());
  EXPECT_TRUE(again.ok()) << again.status();
  engine->Shutdown();
}

TEST(GpuFaults, OutOfMemoryIsResourceExhaustedAndKeepsNothing) {
  const FaultDir faults;
  auto engine = FaultyEngine(faults);
  ASSERT_NE(engine, nullptr);
  const EngineStats baseline = engine->stats();

  faults.Trigger("gpu_oom");
  EXPECT_STATUS(StatusOf(engine->LoadScene(testing::SceneFromBytes(QuadScene().dump()))),
                kResourceExhausted, "(GL_OUT_OF_MEMORY)");
  EXPECT_FALSE(faults.Pending("gpu_oom"));
  EXPECT_TRUE(Eventually([&] {
    const EngineStats now = engine->stats();
    return now.memory_used_bytes == baseline.memory_used_bytes && now.scenes == 0 &&
           now.gl_object_bytes == baseline.gl_object_bytes;
  })) << "the failed load kept memory";

  auto info = engine->LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  ASSERT_TRUE(info.ok()) << info.status();
  // The G-buffer of a new view.
  faults.Trigger("gpu_oom");
  EXPECT_STATUS(StatusOf(engine->Render(Request(info->id, "direct"))), kResourceExhausted,
                "of G-buffer, which the GPU could not allocate (GL_OUT_OF_MEMORY)");
  auto frame = engine->Render(Request(info->id, "direct"));
  ASSERT_TRUE(frame.ok()) << frame.status();
  EXPECT_EQ(testing::DecodeExr(*frame).non_finite(), 0u);
  engine->Shutdown();
}

TEST(GpuFaultsDeathTest, ResetThatCannotBeRecoveredExitsWithStatus70) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        const FaultDir faults;
        auto engine = FaultyEngine(faults);
        if (engine == nullptr) std::exit(1);
        auto info = engine->LoadScene(testing::SceneFromBytes(QuadScene().dump()));
        if (!info.ok()) std::exit(2);
        faults.Trigger("gpu_reset_fail");
        (void)engine->Render(Request(info->id, "direct"));
      },
      ::testing::ExitedWithCode(70), "GPU reset: recovery failed");
}

// Over the wire: the session stream ends UNAVAILABLE, health is SERVING
// again after the recovery, and the next call works.
TEST(GpuFaults, OverTheWireTheSessionEndsUnavailableAndTheServerGoesOn) {
  const FaultDir faults;
  auto engine = FaultyEngine(faults);
  ASSERT_NE(engine, nullptr);
  auto info = engine->LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  ASSERT_TRUE(info.ok()) << info.status();
  {
    testing::TestServer server(*engine);
    grpc::ClientContext context;
    testing::SetDeadline(&context);
    auto stream = server.stub().Session(&context);
    ASSERT_TRUE(stream->Write(testing::ConfigRequest(info->id, 16, 16, /*on_request=*/false)));
    testing::pb::SessionEvent event;
    bool framed = false;
    while (!framed && stream->Read(&event)) framed = event.has_frame();
    ASSERT_TRUE(framed);
    faults.Trigger("gpu_reset");
    while (stream->Read(&event)) {
    }
    const grpc::Status status = stream->Finish();
    EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE) << status.error_message();
    EXPECT_NE(status.error_message().find("GPU reset"), std::string::npos)
        << status.error_message();

    EXPECT_TRUE(Eventually([&] {
      grpc::ClientContext health_context;
      testing::SetDeadline(&health_context);
      ::grpc::health::v1::HealthCheckRequest request;
      ::grpc::health::v1::HealthCheckResponse response;
      return server.health().Check(&health_context, request, &response).ok() &&
             response.status() == ::grpc::health::v1::HealthCheckResponse::SERVING;
    }));
    grpc::ClientContext render_context;
    testing::SetDeadline(&render_context);
    testing::pb::RenderRequest render;
    render.set_scene_id(info->id);
    render.set_width(16);
    render.set_height(16);
    testing::pb::Frame frame;
    const grpc::Status rendered = server.stub().Render(&render_context, render, &frame);
    EXPECT_TRUE(rendered.ok()) << rendered.error_message();
    EXPECT_FALSE(frame.image().empty());
  }  // the server shuts the engine down: it must not hang
}

}  // namespace gpu_faults_test
}  // namespace gistream::reliability
