// Tenancy against the real Engine (EGL; llvmpipe without a GPU), over a
// loopback server with bearer tokens: unguessable scene ids, NOT_FOUND for
// another tenant's id, a named scene shared within a tenant and not across
// (two tenants' cornell_box do not see each other's updates), scene lifetime
// counted over loads, sessions and in-flight Renders, quotas per tenant, and
// idle sessions and scenes expiring.
#include <absl/strings/match.h>
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <thread>

#include "test_server.h"

namespace gistream::testing {
namespace tenancy_test {

using namespace std::chrono_literals;

constexpr const char* kAlice = "alice-token-0123456789";
constexpr const char* kAliceToo = "alice-second-token-0123";  // a collaborator
constexpr const char* kBob = "bob-token-abcdefghijkl";
constexpr const char* kQuota = "quota-token-abcdefghij";  // tenant "tight"
constexpr const char* kGpu = "gpu-quota-token-abcdefg";   // tenant "gpu", 1 MiB of GPU

std::string SceneFile(const std::string& name) {
  std::ifstream in(std::string(GISTREAM_SOURCE_DIR "/scenes/") + name, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

class TenancyTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    absl::StatusOr<AuthTokens> tokens = AuthTokens::Parse(
        absl::StrCat(kAlice, " alice\n", kAliceToo, " alice\n", kBob, " bob\n", kQuota,
                     " tight scenes=2 sessions=1 upload_bytes=100000 gpu_bytes=150000\n", kGpu,
                     " gpu gpu_bytes=1048576\n"));
    ASSERT_TRUE(tokens.ok()) << tokens.status();
    EngineOptions options;
    options.scene_dir = GISTREAM_SOURCE_DIR "/scenes";
    options.quotas = tokens->quotas();
    absl::StatusOr<std::unique_ptr<Engine>> engine = Engine::Create(options);
    ASSERT_TRUE(engine.ok()) << engine.status();  // GL tests never skip
    engine_ = engine->release();
    service::ServerOptions server;
    server.service.tokens = std::make_shared<const AuthTokens>(*std::move(tokens));
    server_ = new TestServer(*engine_, server);
  }
  static void TearDownTestSuite() {
    delete server_;  // shuts the engine down
    delete engine_;
    server_ = nullptr;
    engine_ = nullptr;
  }

  static pb::Gistream::Stub& stub() { return server_->stub(); }
  static void Auth(grpc::ClientContext* context, const char* token) {
    SetDeadline(context, 120s);  // llvmpipe is slow
    context->AddMetadata("authorization", absl::StrCat("Bearer ", token));
  }

  static grpc::Status Load(const char* token, const pb::LoadSceneRequest& request,
                           std::string* id) {
    grpc::ClientContext context;
    Auth(&context, token);
    pb::LoadSceneResponse response;
    const grpc::Status status = stub().LoadScene(&context, request, &response);
    *id = response.scene_id();
    return status;
  }
  static std::string LoadByName(const char* token, const std::string& name) {
    pb::LoadSceneRequest request;
    request.set_name(name);
    std::string id;
    const grpc::Status status = Load(token, request, &id);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return id;
  }
  static grpc::Status Unload(const char* token, const std::string& id) {
    grpc::ClientContext context;
    Auth(&context, token);
    pb::UnloadSceneRequest request;
    request.set_scene_id(id);
    pb::UnloadSceneResponse response;
    return stub().UnloadScene(&context, request, &response);
  }
  // A 32x32 PNG of `id` with the direct solver, after `updates`.
  static grpc::Status Render(const char* token, const std::string& id, pb::Frame* frame,
                             std::vector<pb::Update> updates = {}) {
    grpc::ClientContext context;
    Auth(&context, token);
    pb::RenderRequest request;
    request.set_scene_id(id);
    request.set_width(32);
    request.set_height(32);
    request.mutable_encoding()->set_format(pb::IMAGE_FORMAT_PNG);
    for (pb::Update& u : updates) *request.add_updates() = std::move(u);
    return stub().Render(&context, request, frame);
  }
  static pb::ServerStatus Status(const char* token) {
    grpc::ClientContext context;
    Auth(&context, token);
    pb::ServerStatus status;
    EXPECT_TRUE(stub().GetServerStatus(&context, {}, &status).ok());
    return status;
  }
  static bool Lists(const pb::ServerStatus& status, const std::string& id) {
    return std::find(status.scene_ids().begin(), status.scene_ids().end(), id) !=
           status.scene_ids().end();
  }
  // Opens an on-request session; the first event (opened or the end).
  static std::unique_ptr<Stream> Open(grpc::ClientContext* context, const char* token,
                                      const std::string& scene, pb::SessionEvent* first) {
    Auth(context, token);
    auto stream = stub().Session(context);
    EXPECT_TRUE(stream->Write(ConfigRequest(scene, 32, 32, /*on_request=*/true)));
    if (!stream->Read(first)) first->Clear();
    return stream;
  }

  static inline Engine* engine_ = nullptr;
  static inline TestServer* server_ = nullptr;
};

TEST_F(TenancyTest, IdsAreUnguessableAndOtherTenantsGetNotFound) {
  const std::string id = LoadByName(kAlice, "cornell_box");
  EXPECT_TRUE(std::regex_match(id, std::regex("cornell_box-[0-9a-f]{32}"))) << id;

  pb::Frame frame;
  EXPECT_EQ(Render(kBob, id, &frame).error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(Unload(kBob, id).error_code(), grpc::StatusCode::NOT_FOUND);
  {
    grpc::ClientContext context;
    pb::SessionEvent first;
    auto stream = Open(&context, kBob, id, &first);
    EXPECT_FALSE(first.has_opened());
    stream->WritesDone();
    EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::NOT_FOUND);
  }
  EXPECT_FALSE(Lists(Status(kBob), id));
  EXPECT_TRUE(Lists(Status(kAlice), id));
  // Server-wide figures are not a tenant's to see: Bob, who rendered
  // nothing and holds nothing, sees no frames, memory or process figures
  // after Alice's render.
  ASSERT_TRUE(Render(kAlice, id, &frame).ok());
  const pb::ServerStatus bob = Status(kBob);
  EXPECT_EQ(bob.frames_rendered(), 0u);
  EXPECT_EQ(bob.sessions(), 0u);
  EXPECT_EQ(bob.scenes(), 0u);
  EXPECT_EQ(bob.gl_object_bytes(), 0u);
  EXPECT_EQ(bob.memory_budget_used_bytes(), 0u);
  EXPECT_EQ(bob.rss_bytes(), 0u);
  EXPECT_EQ(bob.cpu_seconds(), 0.0);
  EXPECT_FALSE(bob.version().empty());  // what the server is stays public
  // The owner's calls work, also from another of its tokens.
  EXPECT_TRUE(Render(kAliceToo, id, &frame).ok());
  EXPECT_TRUE(Unload(kAlice, id).ok());
  EXPECT_EQ(Unload(kAlice, id).error_code(), grpc::StatusCode::NOT_FOUND);  // freed
}

TEST_F(TenancyTest, TwoTenantsLoadingCornellBoxDoNotSeeEachOthersUpdates) {
  const std::string alice = LoadByName(kAlice, "cornell_box");
  const std::string bob = LoadByName(kBob, "cornell_box");
  ASSERT_NE(alice, bob);
  // Within a tenant the named scene is shared (the collaborative case).
  EXPECT_EQ(LoadByName(kAliceToo, "cornell_box"), alice);

  pb::Frame bob_before;
  ASSERT_TRUE(Render(kBob, bob, &bob_before).ok());
  // Alice moves node 0 (a scene update, not a camera one: it stays).
  pb::Frame alice_after;
  std::vector<pb::Update> move = {NodeUpdate(1, 0, 0.25f).update()};
  ASSERT_TRUE(Render(kAlice, alice, &alice_after, move).ok());
  EXPECT_GT(alice_after.scene_version(), bob_before.scene_version());
  pb::Frame alice_collaborator;
  ASSERT_TRUE(Render(kAliceToo, alice, &alice_collaborator).ok());
  EXPECT_EQ(alice_collaborator.scene_version(), alice_after.scene_version());

  pb::Frame bob_after;
  ASSERT_TRUE(Render(kBob, bob, &bob_after).ok());
  EXPECT_EQ(bob_after.scene_version(), bob_before.scene_version());
  EXPECT_EQ(bob_after.image(), bob_before.image());  // same state, same pixels

  EXPECT_TRUE(Unload(kAlice, alice).ok());
  EXPECT_TRUE(Unload(kAliceToo, alice).ok());
  EXPECT_TRUE(Unload(kBob, bob).ok());
}

TEST_F(TenancyTest, AnotherClientsLoadRenderUnloadLeavesTheSceneInUse) {
  // Client 1 renders through Render calls only; client 2 of the same
  // tenant does what `gistream render` does: load, render, unload.
  const std::string scene = LoadByName(kAlice, "cornell_box");
  pb::Frame frame;
  ASSERT_TRUE(Render(kAlice, scene, &frame).ok());
  const std::string again = LoadByName(kAliceToo, "cornell_box");
  ASSERT_EQ(again, scene);
  ASSERT_TRUE(Render(kAliceToo, again, &frame).ok());
  ASSERT_TRUE(Unload(kAliceToo, again).ok());
  const grpc::Status after = Render(kAlice, scene, &frame);
  EXPECT_TRUE(after.ok()) << after.error_message();
  EXPECT_TRUE(Unload(kAlice, scene).ok());
}

TEST_F(TenancyTest, UnloadDuringASessionFreesTheSceneWhenItEnds) {
  const std::string scene = LoadByName(kAlice, "cornell_box");
  grpc::ClientContext context;
  pb::SessionEvent event;
  auto stream = Open(&context, kAlice, scene, &event);
  ASSERT_TRUE(event.has_opened()) << event.DebugString();
  ASSERT_TRUE(Unload(kAlice, scene).ok());  // the session still holds it
  ASSERT_TRUE(stream->Write(FrameRequest(1)));
  ASSERT_TRUE(stream->Read(&event));
  EXPECT_TRUE(event.has_frame()) << event.DebugString();
  EXPECT_TRUE(Lists(Status(kAlice), scene));
  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
  EXPECT_TRUE(WaitFor([&] { return !Lists(Status(kAlice), scene); }));
}

TEST_F(TenancyTest, RenderInFlightKeepsItsSceneAfterTheLastUnload) {
  // The engine's Render polls `cancelled` while the frame is made: the
  // first poll unloads the scene's only load reference. A sliced pathtrace
  // frame (256 samples per pixel in 1 ms slices) is in flight for many polls.
  bool unloaded_in_flight = false;
  for (int attempt = 0; attempt < 5 && !unloaded_in_flight; ++attempt) {
    SceneSource source;
    source.tenant = "carol";
    source.name = "cornell_box";
    absl::StatusOr<SceneInfo> info = engine_->LoadScene(source);
    ASSERT_TRUE(info.ok()) << info.status();
    RenderRequest request;
    request.tenant = "carol";
    request.scene = info->id;
    request.solver = "pathtrace";
    request.params["spp"] = "256";
    request.width = 64;
    request.height = 64;
    request.frame_budget_ms = 1.0;
    absl::Status unload;
    request.cancelled = [&] {
      if (!unloaded_in_flight) {
        unloaded_in_flight = true;
        unload = engine_->UnloadScene(info->id, "carol");
      }
      return false;
    };
    absl::StatusOr<EncodedFrame> frame = engine_->Render(request);
    if (!unloaded_in_flight) {
      ASSERT_TRUE(engine_->UnloadScene(info->id, "carol").ok());
      continue;  // the frame was done before the first poll
    }
    EXPECT_TRUE(unload.ok()) << unload;
    EXPECT_TRUE(frame.ok()) << frame.status();  // the scene stayed until it was done
    request.cancelled = nullptr;
    EXPECT_EQ(engine_->Render(request).status().code(), absl::StatusCode::kNotFound);
  }
  EXPECT_TRUE(unloaded_in_flight) << "no Render stayed in flight for one poll";
}

TEST_F(TenancyTest, QuotasGiveResourceExhaustedNamingTheQuota) {
  auto expect_quota = [](const grpc::Status& status, const std::string& quota) {
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
    EXPECT_TRUE(absl::StrContains(status.error_message(),
                                  absl::StrCat("quota ", quota, " of tenant 'tight'")))
        << status.error_message();
  };
  std::string id;
  // gpu_bytes=150000: cornell_box takes 193824 bytes on the GPU (frame
  // stat scene_gpu_bytes), furnace and cornell_box_coarse together about
  // 100 KiB (94784; sessions that render nothing hold no G-buffer).
  pb::LoadSceneRequest big;
  big.set_name("cornell_box");
  expect_quota(Load(kQuota, big, &id), "gpu_bytes");
  // upload_bytes=100000.
  pb::LoadSceneRequest upload;
  upload.set_gltf(SceneFile("cornell_box.gltf"));
  ASSERT_GT(upload.gltf().size(), 100000u);
  expect_quota(Load(kQuota, upload, &id), "upload_bytes");
  // scenes=2.
  const std::string a = LoadByName(kQuota, "furnace");
  const std::string b = LoadByName(kQuota, "cornell_box_coarse");
  pb::LoadSceneRequest third;
  third.set_name("dynamic_block");
  expect_quota(Load(kQuota, third, &id), "scenes");
  // A tenant's named scene loaded again is no new scene.
  EXPECT_EQ(LoadByName(kQuota, "furnace"), a);
  // sessions=1.
  grpc::ClientContext one_context, two_context;
  pb::SessionEvent one, two;
  auto first = Open(&one_context, kQuota, a, &one);
  ASSERT_TRUE(one.has_opened()) << one.DebugString();
  auto second = Open(&two_context, kQuota, b, &two);
  EXPECT_FALSE(two.has_opened());
  second->WritesDone();
  expect_quota(second->Finish(), "sessions");
  // Other tenants are not held to it.
  grpc::ClientContext bob_context;
  pb::SessionEvent bob_event;
  const std::string bob_scene = LoadByName(kBob, "furnace");
  auto bob = Open(&bob_context, kBob, bob_scene, &bob_event);
  EXPECT_TRUE(bob_event.has_opened());
  for (auto* s : {first.get(), bob.get()}) {
    s->WritesDone();
    EXPECT_TRUE(s->Finish().ok());
  }
  EXPECT_TRUE(Unload(kQuota, a).ok());
  EXPECT_TRUE(Unload(kQuota, a).ok());
  EXPECT_TRUE(Unload(kQuota, b).ok());
  EXPECT_TRUE(Unload(kBob, bob_scene).ok());
}

// gpu_bytes counts all a tenant's scenes hold on the GPU: the uploads, each
// solver's estimate and each view's G-buffer (the reservations of the
// server's memory budget, attributed to the scene's tenant:
// util/memory_accounts.h). Another tenant is not held to it.
TEST_F(TenancyTest, GpuBytesQuotaCountsSolverEstimatesAndViews) {
  auto render = [](const char* token, const std::string& id, const std::string& solver,
                   uint32_t side) {
    grpc::ClientContext context;
    Auth(&context, token);
    pb::RenderRequest request;
    request.set_scene_id(id);
    request.set_solver(solver);
    request.set_width(side);
    request.set_height(side);
    request.mutable_encoding()->set_format(pb::IMAGE_FORMAT_PNG);
    pb::Frame frame;
    return stub().Render(&context, request, &frame);
  };
  auto expect_quota = [](const grpc::Status& status, const std::string& what) {
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
    EXPECT_TRUE(absl::StrContains(status.error_message(), "quota gpu_bytes of tenant 'gpu'"))
        << status.error_message();
    EXPECT_TRUE(absl::StrContains(status.error_message(), what)) << status.error_message();
  };
  // furnace: 92352 bytes uploaded. pathtrace holds nothing on the GPU but
  // the view's G-buffer (32x32: 69632 bytes): within 1 MiB.
  const std::string mine = LoadByName(kGpu, "furnace");
  const grpc::Status fits = render(kGpu, mine, "pathtrace", 32);
  EXPECT_TRUE(fits.ok()) << fits.error_message();
  // sh_probes' estimate at its defaults (shadow maps for the emitter's area
  // samples and a probe atlas: hundreds of MiB) is not; nor a 512x512
  // G-buffer (17 MiB).
  expect_quota(render(kGpu, mine, "sh_probes", 32), "sh_probes: ");
  expect_quota(render(kGpu, mine, "pathtrace", 512), "width x height: 512x512");
  // Another tenant renders the same; the refusals held nothing back.
  const std::string bobs = LoadByName(kBob, "furnace");
  const grpc::Status bob = render(kBob, bobs, "sh_probes", 32);
  EXPECT_TRUE(bob.ok()) << bob.error_message();
  const grpc::Status again = render(kGpu, mine, "pathtrace", 32);
  EXPECT_TRUE(again.ok()) << again.error_message();
  EXPECT_TRUE(Unload(kGpu, mine).ok());
  EXPECT_TRUE(Unload(kBob, bobs).ok());
}

// A sink that records how its session ended; with `drop` set it reports
// every frame it gets as dropped (a client that stopped reading).
class EndSink final : public FrameSink {
 public:
  void OnFrame(std::shared_ptr<const EncodedFrame>) override {
    if (drop) dropped_.fetch_add(1);
  }
  uint64_t dropped_frames() const override { return dropped_.load(); }
  std::atomic<bool> drop{false};
  void OnUpdateRejected(uint64_t, const absl::Status&) override {}
  void OnSessionFailed(const absl::Status& status) override {
    std::lock_guard lock(mutex_);
    ended_ = status;
  }
  std::optional<absl::Status> ended() const {
    std::lock_guard lock(mutex_);
    return ended_;
  }

 private:
  mutable std::mutex mutex_;
  std::optional<absl::Status> ended_;
  std::atomic<uint64_t> dropped_{0};
};

TEST(IdleTimeout, IdleSessionsAndScenesExpire) {
  EngineOptions options;
  options.scene_dir = GISTREAM_SOURCE_DIR "/scenes";
  options.idle_timeout = 300ms;
  absl::StatusOr<std::unique_ptr<Engine>> engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  SceneSource source;
  source.name = "furnace";
  absl::StatusOr<SceneInfo> info = (*engine)->LoadScene(source);
  ASSERT_TRUE(info.ok()) << info.status();
  SessionConfig config;
  config.scene = info->id;
  config.width = 16;
  config.height = 16;
  config.pacing = Pacing::kOnRequest;
  auto sink = std::make_shared<EndSink>();
  absl::StatusOr<SessionOpenInfo> session = (*engine)->OpenSession(config, sink);
  ASSERT_TRUE(session.ok()) << session.status();
  // No request from the client: the session ends, then (unused) the scene goes.
  ASSERT_TRUE(WaitFor([&] { return sink->ended().has_value(); }));
  EXPECT_EQ(sink->ended()->code(), absl::StatusCode::kDeadlineExceeded) << *sink->ended();
  EXPECT_TRUE(absl::StrContains(sink->ended()->message(), "idle")) << *sink->ended();
  EXPECT_EQ((*engine)->stats().scenes, 1u);  // its session still counts until closed
  (*engine)->CloseSession(session->id);
  EXPECT_TRUE(WaitFor([&] { return (*engine)->stats().scenes == 0; }));
  EXPECT_EQ((*engine)->RequestFrames(session->id, 1).code(), absl::StatusCode::kNotFound);
}

}  // namespace tenancy_test
}  // namespace gistream::testing

namespace gistream::testing {
namespace tenancy_test {

TEST(IdleTimeout, AWatchedContinuousSessionStaysUntilItsFramesAreDropped) {
  EngineOptions options;
  options.scene_dir = GISTREAM_SOURCE_DIR "/scenes";
  options.idle_timeout = 300ms;
  absl::StatusOr<std::unique_ptr<Engine>> engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  SceneSource source;
  source.name = "furnace";
  absl::StatusOr<SceneInfo> info = (*engine)->LoadScene(source);
  ASSERT_TRUE(info.ok()) << info.status();
  SessionConfig config;
  config.scene = info->id;
  config.width = 16;
  config.height = 16;
  config.encoding.send_unchanged = true;  // every frame reaches the sink
  auto sink = std::make_shared<EndSink>();
  absl::StatusOr<SessionOpenInfo> session = (*engine)->OpenSession(config, sink);
  ASSERT_TRUE(session.ok()) << session.status();
  // Frames reach the client: five idle timeouts later it is still open.
  std::this_thread::sleep_for(5 * options.idle_timeout);
  EXPECT_FALSE(sink->ended().has_value()) << *sink->ended();
  // The client stops reading: its frames are dropped and it goes idle.
  sink->drop = true;
  ASSERT_TRUE(WaitFor([&] { return sink->ended().has_value(); }));
  EXPECT_EQ(sink->ended()->code(), absl::StatusCode::kDeadlineExceeded) << *sink->ended();
  (*engine)->CloseSession(session->id);
}

}  // namespace tenancy_test
}  // namespace gistream::testing
