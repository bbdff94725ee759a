// The gRPC service against FakeEngine on a loopback server: status mapping,
// session protocol (config, updates, rejections, frame requests), frame
// dropping for slow readers, cancellation, health and shutdown.
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

#include <absl/strings/match.h>
#include <gtest/gtest.h>

#include "fake_engine.h"
#include "service/session_reactor.h"
#include "test_server.h"

namespace gistream::testing {
namespace service_test {

using namespace std::chrono_literals;
using ::grpc::health::v1::HealthCheckRequest;
using ::grpc::health::v1::HealthCheckResponse;

class ServiceTest : public ::testing::Test {
 protected:
  static EngineOptions Options() {
    EngineOptions o;
    o.max_sessions = 4;
    o.max_scenes = 3;
    o.max_width = 1024;
    o.max_height = 1024;
    return o;
  }

  FakeEngine engine_{Options()};
  TestServer server_{engine_};
  pb::Gistream::Stub& stub() { return server_.stub(); }

  // Opens a session and reads `opened`.
  std::unique_ptr<Stream> Open(grpc::ClientContext* context, const pb::SessionRequest& config,
                               pb::SessionOpened* opened = nullptr) {
    auto stream = stub().Session(context);
    EXPECT_TRUE(stream->Write(config));
    pb::SessionEvent event;
    EXPECT_TRUE(stream->Read(&event));
    EXPECT_TRUE(event.has_opened()) << event.DebugString();
    if (opened != nullptr) *opened = event.opened();
    return stream;
  }

  HealthCheckResponse::ServingStatus Health(const std::string& service) {
    grpc::ClientContext context;
    SetDeadline(&context, 5s);
    HealthCheckRequest request;
    request.set_service(service);
    HealthCheckResponse response;
    const grpc::Status status = server_.health().Check(&context, request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response.status();
  }
};

// ---------------------------------------------------------------- unary

TEST_F(ServiceTest, ListSolversRoundTrip) {
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::ListSolversResponse response;
  ASSERT_TRUE(stub().ListSolvers(&context, pb::ListSolversRequest(), &response).ok());
  ASSERT_EQ(response.solvers_size(), 2);
  const pb::SolverInfo& direct = response.solvers(0);
  EXPECT_EQ(direct.name(), "direct");
  EXPECT_FALSE(direct.description().empty());
  ASSERT_EQ(direct.stages_size(), 3);
  EXPECT_EQ(direct.stages(0), "shadow_maps");
  ASSERT_EQ(direct.params_size(), 2);
  EXPECT_EQ(direct.params(0).name(), "shadow_map_size");
  EXPECT_EQ(direct.params(0).type(), pb::PARAM_TYPE_INT);
  EXPECT_EQ(direct.params(0).default_value(), "1024");
  EXPECT_EQ(direct.params(0).min(), 64.0);
  EXPECT_EQ(direct.params(0).max(), 8192.0);
  const pb::ParamSpec& bands = response.solvers(1).params(1);
  EXPECT_EQ(bands.type(), pb::PARAM_TYPE_ENUM);
  ASSERT_EQ(bands.choices_size(), 2);
  EXPECT_EQ(bands.choices(1), "3");
}

TEST_F(ServiceTest, LoadSceneReturnsSceneInfo) {
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::LoadSceneRequest request;
  request.set_name("cornell_box");
  pb::LoadSceneResponse response;
  ASSERT_TRUE(stub().LoadScene(&context, request, &response).ok());
  EXPECT_FALSE(response.scene_id().empty());
  EXPECT_EQ(response.nodes_size(), static_cast<int>(FakeEngine::kNodes));
  EXPECT_EQ(response.nodes(2).mesh(), -1);
  EXPECT_EQ(response.nodes(0).parent(), -1);
  EXPECT_EQ(response.nodes(0).scale().x(), 1.0f);
  EXPECT_EQ(response.nodes(0).rotation().w(), 1.0f);
  ASSERT_EQ(response.lights_size(), 1);
  EXPECT_EQ(response.lights(0).type(), pb::LIGHT_TYPE_POINT);
  ASSERT_EQ(response.materials_size(), 2);
  EXPECT_EQ(response.materials(0).base_color_size(), 4);
  EXPECT_EQ(response.bounds().max().y(), 2.0f);
  EXPECT_EQ(response.triangle_count(), 36u);
  EXPECT_EQ(response.version(), 1u);
}

TEST_F(ServiceTest, LoadSceneErrorsMapToGrpcCodes) {
  struct Case {
    const char* what;
    pb::LoadSceneRequest request;
    grpc::StatusCode code;
    const char* message_start;
  };
  std::vector<Case> cases;
  {
    Case c{"no source", {}, grpc::StatusCode::INVALID_ARGUMENT, "source:"};
    cases.push_back(c);
  }
  {
    Case c{"unknown name", {}, grpc::StatusCode::NOT_FOUND, "name: no scene 'nope'"};
    c.request.set_name("nope");
    cases.push_back(c);
  }
  {
    Case c{"bad glb", {}, grpc::StatusCode::INVALID_ARGUMENT, "gltf: not a binary glTF"};
    c.request.set_gltf("definitely not a glb file");
    cases.push_back(c);
  }
  {
    Case c{"missing environment", {}, grpc::StatusCode::NOT_FOUND, "environment_name:"};
    c.request.set_name("furnace");
    c.request.set_environment_name("nope.hdr");
    cases.push_back(c);
  }
  for (const Case& c : cases) {
    grpc::ClientContext context;
    SetDeadline(&context);
    pb::LoadSceneResponse response;
    const grpc::Status status = stub().LoadScene(&context, c.request, &response);
    EXPECT_EQ(status.error_code(), c.code) << c.what << ": " << status.error_message();
    EXPECT_TRUE(absl::StartsWith(status.error_message(), c.message_start))
        << c.what << ": " << status.error_message();
  }

  // max_scenes = 3: the fourth load is refused.
  for (int i = 0; i < 3; ++i) LoadSceneOrDie(stub(), "furnace");
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::LoadSceneRequest request;
  request.set_name("furnace");
  pb::LoadSceneResponse response;
  const grpc::Status status = stub().LoadScene(&context, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_FALSE(status.error_message().empty());
}

// A LoadScene's upload is reserved from the memory budget as soon as the
// caller is authenticated, before it waits for a worker, and held until
// its load ends: uploads queued together cannot pass the budget, and one
// that does not fit is refused before it is copied or parsed (issue 30,
// item 4).
TEST(UploadBudget, AnUploadIsReservedBeforeItsLoadAndReturnedAfter) {
  EngineOptions options;
  options.max_memory_bytes = 1 << 20;
  FakeEngine engine(options);
  TestServer server(engine);
  auto load = [&](size_t bytes, pb::LoadSceneResponse* response) {
    grpc::ClientContext context;
    SetDeadline(&context);
    pb::LoadSceneRequest request;
    std::string glb = "glTF";
    glb.resize(bytes, '\0');
    request.set_gltf(glb);
    return server.stub().LoadScene(&context, request, response);
  };
  pb::LoadSceneResponse response;
  // Larger than the whole budget: refused, naming the upload and the budget.
  const grpc::Status big = load(2 << 20, &response);
  EXPECT_EQ(big.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << big.error_message();
  EXPECT_TRUE(absl::StrContains(big.error_message(), "LoadScene: 2097152 bytes uploaded"))
      << big.error_message();
  EXPECT_TRUE(absl::StrContains(big.error_message(), "memory budget")) << big.error_message();
  EXPECT_EQ(engine.upload_bytes_during_load(), 0u) << "the refused upload never reached a load";
  // One that fits: held while its load runs, returned after.
  const grpc::Status fits = load(64 << 10, &response);
  EXPECT_TRUE(fits.ok()) << fits.error_message();
  EXPECT_EQ(engine.upload_bytes_during_load(), uint64_t(64 << 10));
  EXPECT_TRUE(WaitFor([&] { return engine.upload_budget().used() == 0; }));
  // Others' uploads in flight (held here) leave less: the same upload is
  // refused while they hold the budget, and fits again once they are done.
  {
    auto others = engine.upload_budget().Reserve((1 << 20) - (32 << 10), "others");
    ASSERT_TRUE(others.ok());
    const grpc::Status queued = load(64 << 10, &response);
    EXPECT_EQ(queued.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  }
  EXPECT_TRUE(load(64 << 10, &response).ok());
}

TEST_F(ServiceTest, UnloadSceneStatuses) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext session_context;
  SetDeadline(&session_context);
  auto stream = Open(&session_context, ConfigRequest(scene, 16, 16, /*on_request=*/true));

  auto unload = [&](const std::string& id) {
    grpc::ClientContext context;
    SetDeadline(&context);
    pb::UnloadSceneRequest request;
    request.set_scene_id(id);
    pb::UnloadSceneResponse response;
    return stub().UnloadScene(&context, request, &response);
  };
  EXPECT_EQ(unload(scene).error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_EQ(unload("nope").error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(unload("").error_code(), grpc::StatusCode::INVALID_ARGUMENT);

  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
  ASSERT_TRUE(WaitFor([&] { return engine_.session_count() == 0; }));
  EXPECT_TRUE(unload(scene).ok());
}

TEST_F(ServiceTest, RenderReturnsAFrameWithTimings) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::RenderRequest request;
  request.set_scene_id(scene);
  request.set_width(32);
  request.set_height(24);
  request.mutable_encoding()->set_format(pb::IMAGE_FORMAT_PNG);
  pb::Update* u = request.add_updates();
  u->set_seq(42);
  u->mutable_node_transform()->set_node(1);
  pb::Frame frame;
  const grpc::Status status = stub().Render(&context, request, &frame);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(frame.width(), 32u);
  EXPECT_EQ(frame.height(), 24u);
  EXPECT_EQ(frame.format(), pb::IMAGE_FORMAT_PNG);
  EXPECT_EQ(frame.image().size(), 32u * 24u * 4u);
  EXPECT_EQ(frame.last_update_seq(), 42u);
  EXPECT_EQ(frame.solver(), "direct");
  ASSERT_EQ(frame.timings_size(), 3);
  EXPECT_EQ(frame.timings(0).name(), "apply_updates");
  EXPECT_EQ(frame.timings(1).name(), "shade");
  EXPECT_EQ(frame.timings(2).name(), "encode");
}

TEST_F(ServiceTest, RenderErrorsNameTheField) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  auto render = [&](const pb::RenderRequest& request) {
    grpc::ClientContext context;
    SetDeadline(&context);
    pb::Frame frame;
    return stub().Render(&context, request, &frame);
  };
  pb::RenderRequest request;
  request.set_scene_id(scene);
  request.add_updates()->mutable_node_transform()->add_matrix(1.0f);
  grpc::Status status = render(request);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(status.error_message(), "updates[0].node_transform.matrix: expected 16 floats, got 1");

  request.clear_updates();
  request.add_updates()->mutable_node_transform()->set_node(99);
  status = render(request);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_TRUE(absl::StartsWith(status.error_message(), "updates[0].node_transform.node"))
      << status.error_message();

  request.clear_updates();
  request.set_width(5000);
  request.set_height(10);
  status = render(request);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_TRUE(absl::StartsWith(status.error_message(), "width:")) << status.error_message();
}

TEST_F(ServiceTest, GetServerStatus) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::ServerStatus status;
  ASSERT_TRUE(stub().GetServerStatus(&context, pb::GetServerStatusRequest(), &status).ok());
  EXPECT_EQ(status.gl_renderer(), "fake engine (CPU)");
  EXPECT_EQ(status.scenes(), 1u);
  EXPECT_EQ(status.sessions(), 0u);
  ASSERT_EQ(status.scene_ids_size(), 1);
  EXPECT_EQ(status.scene_ids(0), scene);
}

// ---------------------------------------------------------------- sessions

TEST_F(ServiceTest, TwoConcurrentSessionsApplyUpdatesInOrderAndEchoSeq) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");

  // A: on-request. Updates, then one frame that must include all of them.
  // B: continuous at 120 fps. Frames must echo a non-decreasing seq that
  //    reaches the last update sent.
  std::vector<uint64_t> sent_a, sent_b;
  std::string id_a, id_b;
  auto run_a = [&] {
    grpc::ClientContext context;
    SetDeadline(&context);
    pb::SessionOpened opened;
    auto stream = Open(&context, ConfigRequest(scene, 64, 48, /*on_request=*/true), &opened);
    id_a = opened.session_id();
    EXPECT_EQ(opened.solver(), "direct");
    EXPECT_EQ(opened.params().at("shadow_map_size"), "1024");  // defaults filled in
    for (uint64_t seq = 1; seq <= 20; ++seq) {
      EXPECT_TRUE(stream->Write(NodeUpdate(seq, static_cast<uint32_t>(seq % 3), 0.1f * seq)));
      sent_a.push_back(seq);
    }
    EXPECT_TRUE(stream->Write(FrameRequest(1)));
    pb::SessionEvent event;
    ASSERT_TRUE(stream->Read(&event));
    ASSERT_TRUE(event.has_frame()) << event.DebugString();
    EXPECT_EQ(event.frame().last_update_seq(), 20u);
    EXPECT_EQ(event.frame().width(), 64u);
    EXPECT_EQ(event.frame().height(), 48u);
    EXPECT_GT(event.frame().timings_size(), 0);
    stream->WritesDone();
    EXPECT_TRUE(stream->Finish().ok());
  };
  auto run_b = [&] {
    grpc::ClientContext context;
    SetDeadline(&context);
    pb::SessionOpened opened;
    auto stream =
        Open(&context, ConfigRequest(scene, 32, 32, /*on_request=*/false, 120.0f), &opened);
    id_b = opened.session_id();
    for (uint64_t seq = 100; seq <= 130; ++seq) {
      EXPECT_TRUE(stream->Write(NodeUpdate(seq, 1, 0.0f)));
      sent_b.push_back(seq);
    }
    uint64_t last_seq = 0;
    uint64_t last_frame = 0;
    int frames = 0;
    pb::SessionEvent event;
    while (last_seq < 130 && stream->Read(&event)) {
      ASSERT_TRUE(event.has_frame()) << event.DebugString();
      const pb::Frame& f = event.frame();
      EXPECT_GE(f.last_update_seq(), last_seq);
      EXPECT_GT(f.frame_number(), last_frame);
      EXPECT_GT(f.timings_size(), 0);
      for (const pb::StageTiming& t : f.timings()) EXPECT_FALSE(t.name().empty());
      last_seq = f.last_update_seq();
      last_frame = f.frame_number();
      ++frames;
    }
    EXPECT_EQ(last_seq, 130u);
    EXPECT_GT(frames, 0);
    context.TryCancel();
    stream->Finish();
  };
  std::thread a(run_a);
  std::thread b(run_b);
  a.join();
  b.join();
  EXPECT_NE(id_a, id_b);
  EXPECT_EQ(engine_.applied_seqs(id_a), sent_a);
  EXPECT_EQ(engine_.applied_seqs(id_b), sent_b);
  EXPECT_TRUE(WaitFor([&] { return engine_.session_count() == 0; }));
}

TEST_F(ServiceTest, RejectedUpdatesAreEventsAndTheStreamGoesOn) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  auto stream = Open(&context, ConfigRequest(scene, 16, 16, /*on_request=*/true));
  pb::SessionEvent event;

  // Rejected by translation (wire form).
  pb::SessionRequest bad_matrix = NodeUpdate(1, 0, 0.0f);
  for (int i = 0; i < 5; ++i)
    bad_matrix.mutable_update()->mutable_node_transform()->add_matrix(1.0f);
  ASSERT_TRUE(stream->Write(bad_matrix));
  ASSERT_TRUE(ReadNonFrame(*stream, &event));
  ASSERT_TRUE(event.has_rejected()) << event.DebugString();
  EXPECT_EQ(event.rejected().seq(), 1u);
  EXPECT_EQ(event.rejected().code(), static_cast<int>(grpc::StatusCode::INVALID_ARGUMENT));
  EXPECT_EQ(event.rejected().message(), "update.node_transform.matrix: expected 16 floats, got 5");

  // Rejected synchronously by Engine::PushUpdate.
  ASSERT_TRUE(stream->Write(NodeUpdate(2, 99, 0.0f)));
  ASSERT_TRUE(ReadNonFrame(*stream, &event));
  ASSERT_TRUE(event.has_rejected());
  EXPECT_EQ(event.rejected().seq(), 2u);
  EXPECT_EQ(event.rejected().code(), static_cast<int>(grpc::StatusCode::NOT_FOUND));

  // An update with no change.
  pb::SessionRequest empty;
  empty.mutable_update()->set_seq(3);
  ASSERT_TRUE(stream->Write(empty));
  ASSERT_TRUE(ReadNonFrame(*stream, &event));
  ASSERT_TRUE(event.has_rejected());
  EXPECT_EQ(event.rejected().seq(), 3u);
  EXPECT_EQ(event.rejected().code(), static_cast<int>(grpc::StatusCode::INVALID_ARGUMENT));

  // A second config.
  ASSERT_TRUE(stream->Write(ConfigRequest(scene, 16, 16, true)));
  ASSERT_TRUE(ReadNonFrame(*stream, &event));
  ASSERT_TRUE(event.has_rejected());
  EXPECT_EQ(event.rejected().code(), static_cast<int>(grpc::StatusCode::INVALID_ARGUMENT));
  EXPECT_TRUE(absl::StartsWith(event.rejected().message(), "config:"));

  // Rejected later, on the engine's render thread, through the sink.
  pb::SessionRequest bad_material;
  bad_material.mutable_update()->set_seq(4);
  bad_material.mutable_update()->mutable_material()->set_material(7);
  ASSERT_TRUE(stream->Write(bad_material));
  ASSERT_TRUE(stream->Write(NodeUpdate(5, 0, 1.0f)));
  ASSERT_TRUE(stream->Write(FrameRequest(1)));
  bool saw_rejected = false;
  bool saw_frame = false;
  while ((!saw_rejected || !saw_frame) && stream->Read(&event)) {
    if (event.has_rejected()) {
      EXPECT_EQ(event.rejected().seq(), 4u);
      EXPECT_EQ(event.rejected().code(), static_cast<int>(grpc::StatusCode::NOT_FOUND));
      saw_rejected = true;
    } else if (event.has_frame()) {
      EXPECT_EQ(event.frame().last_update_seq(), 5u);  // the good update still applied
      saw_frame = true;
    }
  }
  EXPECT_TRUE(saw_rejected);
  EXPECT_TRUE(saw_frame);
  EXPECT_EQ(engine_.session_count(), 1u);  // still open

  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
}

TEST_F(ServiceTest, InvalidFirstMessageEndsTheCall) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  struct Case {
    const char* what;
    pb::SessionRequest first;
    grpc::StatusCode code;
    const char* message_start;
  };
  std::vector<Case> cases;
  cases.push_back({"update first", NodeUpdate(1, 0, 0.0f), grpc::StatusCode::INVALID_ARGUMENT,
                   "config: the first SessionRequest must be a config"});
  {
    Case c{"unknown solver", ConfigRequest(scene, 16, 16, true), grpc::StatusCode::NOT_FOUND,
           "solver:"};
    c.first.mutable_config()->set_solver("nope");
    cases.push_back(c);
  }
  {
    Case c{"unknown param", ConfigRequest(scene, 16, 16, true), grpc::StatusCode::INVALID_ARGUMENT,
           "params.bogus"};
    (*c.first.mutable_config()->mutable_params())["bogus"] = "1";
    cases.push_back(c);
  }
  {
    Case c{"width only", ConfigRequest(scene, 16, 16, true), grpc::StatusCode::INVALID_ARGUMENT,
           "config.width: set without config.height"};
    c.first.mutable_config()->set_height(0);
    cases.push_back(c);
  }
  cases.push_back({"too large", ConfigRequest(scene, 5000, 16, true),
                   grpc::StatusCode::INVALID_ARGUMENT, "width:"});
  cases.push_back({"unknown scene", ConfigRequest("nope", 16, 16, true),
                   grpc::StatusCode::NOT_FOUND, "scene_id:"});

  for (const Case& c : cases) {
    grpc::ClientContext context;
    SetDeadline(&context);
    auto stream = stub().Session(&context);
    stream->Write(c.first);
    pb::SessionEvent event;
    EXPECT_FALSE(stream->Read(&event)) << c.what << ": " << event.DebugString();
    const grpc::Status status = stream->Finish();
    EXPECT_EQ(status.error_code(), c.code) << c.what << ": " << status.error_message();
    EXPECT_TRUE(absl::StartsWith(status.error_message(), c.message_start))
        << c.what << ": " << status.error_message();
  }
  EXPECT_EQ(engine_.session_count(), 0u);
}

TEST_F(ServiceTest, StreamClosedBeforeConfigIsInvalidArgument) {
  grpc::ClientContext context;
  SetDeadline(&context);
  auto stream = stub().Session(&context);
  stream->WritesDone();
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
}

TEST_F(ServiceTest, TooManySessionsIsResourceExhausted) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  std::vector<std::unique_ptr<grpc::ClientContext>> contexts;
  std::vector<std::unique_ptr<Stream>> streams;
  for (int i = 0; i < 4; ++i) {  // max_sessions = 4
    contexts.push_back(std::make_unique<grpc::ClientContext>());
    SetDeadline(contexts.back().get());
    streams.push_back(Open(contexts.back().get(), ConfigRequest(scene, 8, 8, true)));
  }
  grpc::ClientContext context;
  SetDeadline(&context);
  auto stream = stub().Session(&context);
  stream->Write(ConfigRequest(scene, 8, 8, true));
  pb::SessionEvent event;
  EXPECT_FALSE(stream->Read(&event));
  EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  for (auto& c : contexts) c->TryCancel();
  for (auto& s : streams) s->Finish();
  EXPECT_TRUE(WaitFor([&] { return engine_.session_count() == 0; }));
}

TEST_F(ServiceTest, OnRequestSessionEndsAfterRequestedFramesOnHalfClose) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  auto stream = Open(&context, ConfigRequest(scene, 16, 16, /*on_request=*/true));
  ASSERT_TRUE(stream->Write(FrameRequest(3)));
  stream->WritesDone();
  int frames = 0;
  pb::SessionEvent event;
  while (stream->Read(&event)) {
    EXPECT_TRUE(event.has_frame());
    ++frames;
  }
  EXPECT_EQ(frames, 3);
  EXPECT_TRUE(stream->Finish().ok());
  EXPECT_TRUE(WaitFor([&] { return engine_.session_count() == 0; }));
}

TEST_F(ServiceTest, CancelledClientFreesItsSession) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  auto stream = Open(&context, ConfigRequest(scene, 32, 32, /*on_request=*/false, 60.0f));
  pb::SessionEvent event;
  ASSERT_TRUE(stream->Read(&event));  // mid-stream
  EXPECT_TRUE(event.has_frame());
  EXPECT_EQ(engine_.session_count(), 1u);
  context.TryCancel();
  EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::CANCELLED);
  EXPECT_TRUE(WaitFor([&] { return engine_.session_count() == 0; }, 5s));
  // The fake calls a closed session's sink once more: it must be harmless.
  EXPECT_TRUE(WaitFor([&] { return engine_.sink_calls_after_close() >= 1; }, 5s));
}

TEST_F(ServiceTest, ClientThatDisappearsFreesItsSession) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  {
    // Own channel, destroyed without finishing the call.
    auto channel = grpc::CreateChannel(server_.address(), grpc::InsecureChannelCredentials());
    auto stub2 = pb::Gistream::NewStub(channel);
    auto context = std::make_unique<grpc::ClientContext>();
    auto stream = stub2->Session(context.get());
    ASSERT_TRUE(stream->Write(ConfigRequest(scene, 16, 16, false, 30.0f)));
    pb::SessionEvent event;
    ASSERT_TRUE(stream->Read(&event));
    ASSERT_TRUE(event.has_opened());
    ASSERT_EQ(engine_.session_count(), 1u);
    context->TryCancel();  // what a dying process's transport amounts to
    stream->Finish();
  }
  EXPECT_TRUE(WaitFor([&] { return engine_.session_count() == 0; }, 5s));
}

TEST_F(ServiceTest, CancelWhileOpeningFreesTheSession) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  engine_.HoldOpens();
  grpc::ClientContext context;
  SetDeadline(&context);
  auto stream = stub().Session(&context);
  ASSERT_TRUE(stream->Write(ConfigRequest(scene, 16, 16, true)));
  // The cancel arrives while OpenSession is known to be running.
  ASSERT_TRUE(WaitFor([&] { return engine_.opens_started() == 1; }, 10s));
  context.TryCancel();
  stream->Finish();
  engine_.ReleaseOpens();
  // OpenSession succeeds after the cancel; the service must close it.
  ASSERT_TRUE(WaitFor([&] { return engine_.sessions_opened() == 1; }, 10s));
  EXPECT_TRUE(WaitFor([&] { return engine_.session_count() == 0; }, 10s));
}

TEST_F(ServiceTest, SlowReaderDropsFramesWithoutQueueing) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  // 256x256 RGBA = 256 KiB a frame at 240 fps: ~60 MB/s, far more than a
  // reader that sleeps lets through the HTTP/2 window.
  auto stream = Open(&context, ConfigRequest(scene, 256, 256, /*on_request=*/false, 240.0f));
  int64_t max_live = 0;
  const auto end = std::chrono::steady_clock::now() + 1500ms;
  while (std::chrono::steady_clock::now() < end) {  // not reading
    max_live = std::max(max_live, engine_.live_frames());
    std::this_thread::sleep_for(5ms);
  }
  const uint64_t rendered = engine_.frames_rendered();
  EXPECT_GT(rendered, 100u);
  // The service holds at most the newest unsent frame per session (the one
  // in flight is already a protobuf); the fake's own hand-off adds one.
  EXPECT_LE(max_live, 2);

  uint64_t dropped = 0;
  int frames = 0;
  pb::SessionEvent event;
  while (frames < 40 && stream->Read(&event)) {
    ASSERT_TRUE(event.has_frame());
    dropped += event.frame().dropped_frames();
    ++frames;
  }
  EXPECT_GT(dropped, 0u);
  // What was not delivered was counted as dropped, not kept.
  EXPECT_GT(dropped, rendered / 2);
  context.TryCancel();
  stream->Finish();
  EXPECT_TRUE(WaitFor([&] { return engine_.session_count() == 0; }));
}

TEST_F(ServiceTest, OnRequestSlowReaderGetsEveryFrameAndHoldsTheWindow) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  // 256 KiB frames, far more than a reader that sleeps lets through.
  auto stream = Open(&context, ConfigRequest(scene, 256, 256, /*on_request=*/true));
  constexpr int kFrames = 300;
  ASSERT_TRUE(stream->Write(FrameRequest(kFrames)));
  int64_t max_live = 0;
  const auto end = std::chrono::steady_clock::now() + 1000ms;
  while (std::chrono::steady_clock::now() < end) {  // not reading
    max_live = std::max(max_live, engine_.live_frames());
    std::this_thread::sleep_for(5ms);
  }
  // The engine is asked for the next frames only as earlier ones are
  // written, so a reader that does not read stops the rendering (the fake
  // renders one a millisecond when owed).
  EXPECT_LT(engine_.frames_rendered(), uint64_t{kFrames} / 3);
  EXPECT_LE(max_live, int64_t{service::SessionReactor::kOnRequestWindow} + 1);

  // Every frame asked for arrives, in order, none dropped.
  uint64_t last_number = 0;
  for (int i = 0; i < kFrames; ++i) {
    pb::SessionEvent event;
    ASSERT_TRUE(stream->Read(&event)) << "frame " << i;
    ASSERT_TRUE(event.has_frame());
    EXPECT_EQ(event.frame().dropped_frames(), 0u);
    EXPECT_GT(event.frame().frame_number(), last_number);
    last_number = event.frame().frame_number();
  }
  EXPECT_LE(engine_.max_owed(), uint64_t{service::SessionReactor::kOnRequestWindow});
  stream->WritesDone();
  pb::SessionEvent extra;
  EXPECT_FALSE(stream->Read(&extra));  // nothing more than asked for
  EXPECT_TRUE(stream->Finish().ok());
}

TEST_F(ServiceTest, EngineSessionFailureEndsTheCallWithItsStatus) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::SessionOpened opened;
  auto stream = Open(&context, ConfigRequest(scene, 16, 16, /*on_request=*/true), &opened);
  engine_.FailSession(opened.session_id(), absl::InternalError("GPU reset"));
  pb::SessionEvent event;
  while (stream->Read(&event)) {
  }
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INTERNAL);
  EXPECT_EQ(status.error_message(), "GPU reset");
  EXPECT_TRUE(WaitFor([&] { return engine_.session_count() == 0; }));
}

TEST_F(ServiceTest, FloodOfBadUpdatesWithoutReadingIsBounded) {
  // Rejections are never dropped; a client that does not read them is
  // slowed down (the server stops reading) instead of buffered.
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  auto stream = Open(&context, ConfigRequest(scene, 16, 16, /*on_request=*/true));
  constexpr int kBad = 2000;
  std::thread writer([&] {
    for (int i = 1; i <= kBad; ++i) {
      if (!stream->Write(NodeUpdate(static_cast<uint64_t>(i), 99, 0.0f))) break;
    }
    stream->WritesDone();
  });
  std::this_thread::sleep_for(300ms);
  int rejected = 0;
  uint64_t expect_seq = 1;
  pb::SessionEvent event;
  while (stream->Read(&event)) {
    ASSERT_TRUE(event.has_rejected());
    EXPECT_EQ(event.rejected().seq(), expect_seq++);  // in order, none lost
    ++rejected;
  }
  writer.join();
  EXPECT_EQ(rejected, kBad);
  EXPECT_TRUE(stream->Finish().ok());
}

// ---------------------------------------------------------------- health

TEST_F(ServiceTest, HealthIsServing) {
  EXPECT_EQ(Health(""), HealthCheckResponse::SERVING);
  EXPECT_EQ(Health("gistream.v1.Gistream"), HealthCheckResponse::SERVING);
}

TEST_F(ServiceTest, HealthTurnsNotServingWhenShutdownStarts) {
  // Watch is answered with the current status and then every change; the
  // change to NOT_SERVING must arrive before the server stops.
  grpc::ClientContext context;
  SetDeadline(&context);
  HealthCheckRequest request;
  request.set_service("gistream.v1.Gistream");
  auto watch = server_.health().Watch(&context, request);
  HealthCheckResponse response;
  ASSERT_TRUE(watch->Read(&response));
  EXPECT_EQ(response.status(), HealthCheckResponse::SERVING);

  std::thread shutdown([&] { server_.server().Shutdown(2s); });
  bool saw_not_serving = false;
  while (watch->Read(&response)) {
    if (response.status() == HealthCheckResponse::NOT_SERVING) {
      saw_not_serving = true;
      break;
    }
  }
  EXPECT_TRUE(saw_not_serving);
  context.TryCancel();
  watch->Finish();
  shutdown.join();
}

TEST_F(ServiceTest, SetNotServingIsVisibleToCheck) {
  server_.server().SetNotServing();
  EXPECT_EQ(Health(""), HealthCheckResponse::NOT_SERVING);
  EXPECT_EQ(Health("gistream.v1.Gistream"), HealthCheckResponse::NOT_SERVING);
}

// ---------------------------------------------------------------- shutdown

TEST_F(ServiceTest, ShutdownEndsOpenSessionsWithinTheDeadline) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  auto stream = Open(&context, ConfigRequest(scene, 16, 16, /*on_request=*/false, 30.0f));
  const auto start = std::chrono::steady_clock::now();
  server_.server().Shutdown(500ms);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
  EXPECT_EQ(engine_.session_count(), 0u);
  pb::SessionEvent event;
  while (stream->Read(&event)) {
  }
  EXPECT_FALSE(stream->Finish().ok());
}

// Drain (issue 31): Shutdown tells every session to move (a Draining event
// with the deadline) and returns once the clients have left, well before
// the deadline would have cut them: the call ends OK (the client's
// half-close), not CANCELLED by the deadline.
TEST_F(ServiceTest, ShutdownTellsSessionsToMoveAndEndsWhenTheyLeave) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  auto stream = Open(&context, ConfigRequest(scene, 16, 16, /*on_request=*/false, 30.0f));
  std::thread shutdown([&] { server_.server().Shutdown(60s); });
  pb::SessionEvent event;
  bool draining = false;
  while (!draining && stream->Read(&event)) {
    if (event.has_draining()) {
      draining = true;
      EXPECT_EQ(event.draining().deadline_ms(), 60000u);
      EXPECT_FALSE(event.draining().reason().empty());
    }
  }
  ASSERT_TRUE(draining) << "no Draining event before the call ended";
  // The client moves: it half-closes, and the call ends OK.
  stream->WritesDone();
  while (stream->Read(&event)) {
  }
  EXPECT_TRUE(stream->Finish().ok());
  shutdown.join();  // returns once the last call has ended (not after 60 s)
  EXPECT_EQ(engine_.session_count(), 0u);
}

}  // namespace service_test
}  // namespace gistream::testing
