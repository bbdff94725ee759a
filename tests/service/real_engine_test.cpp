// The key service scenarios against the real Engine (EGL; llvmpipe without
// a GPU): two sessions on cornell_box at 64x64, seq echo, stage timings, a
// cancelled client freeing its session, health. One engine and server for
// the whole suite: creating an EGL context per test is slow, and
// GistreamServer::Shutdown shuts the engine down.
#include <absl/strings/match.h>
#include <gtest/gtest.h>

#include <memory>
#include <thread>

#include "test_server.h"

namespace gistream::testing {
namespace real_engine_test {

using namespace std::chrono_literals;
using ::grpc::health::v1::HealthCheckRequest;
using ::grpc::health::v1::HealthCheckResponse;

class RealEngineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    EngineOptions options;
    options.scene_dir = GISTREAM_SOURCE_DIR "/scenes";
    absl::StatusOr<std::unique_ptr<Engine>> engine = Engine::Create(options);
    if (!engine.ok()) {
      skip_reason_ = new std::string("no usable EGL device: " + engine.status().ToString());
      return;
    }
    engine_ = engine->release();
    server_ = new TestServer(*engine_);
  }
  static void TearDownTestSuite() {
    delete server_;  // shuts the engine down
    delete engine_;
    delete skip_reason_;
    server_ = nullptr;
    engine_ = nullptr;
    skip_reason_ = nullptr;
  }
  void SetUp() override {
    if (skip_reason_ != nullptr) GTEST_SKIP() << *skip_reason_;
  }

  static pb::Gistream::Stub& stub() { return server_->stub(); }
  static uint32_t Sessions() { return engine_->stats().sessions; }

  static pb::SessionRequest CameraUpdate(uint64_t seq, float z) {
    pb::SessionRequest request;
    pb::Update* u = request.mutable_update();
    u->set_seq(seq);
    pb::LookAt* look = u->mutable_camera()->mutable_look_at();
    look->mutable_eye()->set_y(1.0f);
    look->mutable_eye()->set_z(z);
    look->mutable_target()->set_y(1.0f);
    return request;
  }

  static inline Engine* engine_ = nullptr;
  static inline TestServer* server_ = nullptr;
  static inline std::string* skip_reason_ = nullptr;
};

TEST_F(RealEngineTest, HealthIsServing) {
  grpc::ClientContext context;
  SetDeadline(&context);
  HealthCheckRequest request;
  request.set_service("gistream.v1.Gistream");
  HealthCheckResponse response;
  ASSERT_TRUE(server_->health().Check(&context, request, &response).ok());
  EXPECT_EQ(response.status(), HealthCheckResponse::SERVING);
}

TEST_F(RealEngineTest, TwoSessionsOnOneSceneEchoSeqWithTimings) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  ASSERT_FALSE(scene.empty());

  auto run = [&](uint64_t first_seq, bool on_request) {
    grpc::ClientContext context;
    SetDeadline(&context, 120s);  // llvmpipe is slow
    auto stream = stub().Session(&context);
    ASSERT_TRUE(stream->Write(ConfigRequest(scene, 64, 64, on_request, 30.0f)));
    pb::SessionEvent event;
    ASSERT_TRUE(stream->Read(&event));
    ASSERT_TRUE(event.has_opened()) << event.DebugString();
    const uint64_t last = first_seq + 4;
    for (uint64_t seq = first_seq; seq <= last; ++seq) {
      ASSERT_TRUE(stream->Write(CameraUpdate(seq, 3.0f + 0.1f * static_cast<float>(seq))));
    }
    if (on_request) {
      ASSERT_TRUE(stream->Write(FrameRequest(1)));
    }
    uint64_t seen = 0;
    int frames = 0;
    while (seen < last && stream->Read(&event)) {
      ASSERT_TRUE(event.has_frame()) << event.DebugString();
      const pb::Frame& f = event.frame();
      EXPECT_EQ(f.width(), 64u);
      EXPECT_EQ(f.height(), 64u);
      // A frame without a new picture (a keep-alive, when the machine is
      // slow enough that a second passes between changed frames) says so.
      EXPECT_TRUE(!f.image().empty() || f.unchanged());
      EXPECT_GT(f.timings_size(), 0);
      for (const pb::StageTiming& t : f.timings()) EXPECT_FALSE(t.name().empty());
      EXPECT_GE(f.last_update_seq(), seen);
      seen = f.last_update_seq();
      ++frames;
      if (on_request && seen < last) {
        ASSERT_TRUE(stream->Write(FrameRequest(1)));
      }
    }
    EXPECT_EQ(seen, last);
    EXPECT_GT(frames, 0);
    context.TryCancel();
    stream->Finish();
  };
  std::thread a(run, 1, /*on_request=*/true);
  std::thread b(run, 100, /*on_request=*/false);
  a.join();
  b.join();
  EXPECT_TRUE(WaitFor([] { return Sessions() == 0; }, 10s));
}

TEST_F(RealEngineTest, CancelledClientFreesItsSession) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context, 120s);
  auto stream = stub().Session(&context);
  ASSERT_TRUE(stream->Write(ConfigRequest(scene, 64, 64, /*on_request=*/false, 30.0f)));
  pb::SessionEvent event;
  ASSERT_TRUE(stream->Read(&event));
  ASSERT_TRUE(event.has_opened());
  ASSERT_TRUE(stream->Read(&event));  // mid-stream
  EXPECT_TRUE(event.has_frame());
  EXPECT_EQ(Sessions(), 1u);
  context.TryCancel();
  stream->Finish();
  EXPECT_TRUE(WaitFor([] { return Sessions() == 0; }, 10s));
}

TEST_F(RealEngineTest, ServerStatusCountsSessionFramesAndGlObjectBytes) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context, 120s);
  auto stream = stub().Session(&context);
  ASSERT_TRUE(stream->Write(ConfigRequest(scene, 64, 48, /*on_request=*/true)));
  pb::SessionEvent event;
  ASSERT_TRUE(stream->Read(&event));
  ASSERT_TRUE(event.has_opened());
  const std::string id = event.opened().session_id();
  ASSERT_TRUE(stream->Write(CameraUpdate(3, 3.5f)));
  ASSERT_TRUE(stream->Write(FrameRequest(1)));
  ASSERT_TRUE(stream->Read(&event));
  ASSERT_TRUE(event.has_frame());

  grpc::ClientContext status_context;
  SetDeadline(&status_context);
  pb::ServerStatus status;
  ASSERT_TRUE(stub().GetServerStatus(&status_context, pb::GetServerStatusRequest(), &status).ok());
  EXPECT_FALSE(status.version().empty());
  EXPECT_GT(status.rss_bytes(), 0u);
  const pb::SessionStatus* session = nullptr;
  for (const pb::SessionStatus& s : status.session_status()) {
    if (s.session_id() == id) session = &s;
  }
  ASSERT_NE(session, nullptr);
  EXPECT_EQ(session->scene_id(), scene);
  EXPECT_EQ(session->solver(), "direct");
  EXPECT_EQ(session->frames(), 1u);
  EXPECT_EQ(session->width(), 64u);
  EXPECT_EQ(session->height(), 48u);
  EXPECT_EQ(session->last_update_seq(), 3u);
  // The scene's buffers and textures plus this view's G-buffer (68 bytes a pixel).
  EXPECT_GT(status.gl_object_bytes(), 64u * 48u * 68u);
  // llvmpipe reports no GPU memory; a driver that does reports both or the free part.
  EXPECT_LE(status.gpu_memory_available_bytes(), status.gpu_memory_total_bytes() > 0
                                                     ? status.gpu_memory_total_bytes()
                                                     : status.gpu_memory_available_bytes());
  context.TryCancel();
  stream->Finish();
  EXPECT_TRUE(WaitFor([] { return Sessions() == 0; }, 10s));
}

// An unknown solver is NOT_FOUND (solvers/registry.h), an out-of-range
// parameter INVALID_ARGUMENT; both name the field.
TEST_F(RealEngineTest, InvalidConfigNamesTheField) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  struct Case {
    std::string solver, param, field;
    grpc::StatusCode code;
  };
  for (const Case& c :
       {Case{"no_such_solver", "", "solver", grpc::StatusCode::NOT_FOUND},
        Case{"direct", "0", "params.area_samples", grpc::StatusCode::INVALID_ARGUMENT}}) {
    grpc::ClientContext context;
    SetDeadline(&context, 60s);
    auto stream = stub().Session(&context);
    pb::SessionRequest config = ConfigRequest(scene, 64, 64, true);
    config.mutable_config()->set_solver(c.solver);
    if (!c.param.empty()) (*config.mutable_config()->mutable_params())["area_samples"] = c.param;
    stream->Write(config);
    pb::SessionEvent event;
    EXPECT_FALSE(stream->Read(&event));
    const grpc::Status status = stream->Finish();
    EXPECT_EQ(status.error_code(), c.code) << status.error_message();
    EXPECT_TRUE(absl::StrContains(status.error_message(), c.field)) << status.error_message();
  }
}

}  // namespace real_engine_test
}  // namespace gistream::testing
