// The monitoring surface against FakeEngine on a loopback server: the
// Prometheus endpoint (--metrics-listen) scraped over a plain socket, its
// text parsed, and its counters and histograms checked against the frames,
// rejections and failed calls the test caused; GetServerStatus's version,
// process and per-session fields. Counts are compared exactly where the test
// controls them (on-request frames), never against wall-clock time.
#include <absl/strings/match.h>
#include <gtest/gtest.h>

#include "fake_engine.h"
#include "metrics/metrics.h"
#include "prometheus_text.h"
#include "test_server.h"
#include "util/version.h"

namespace gistream::testing {
namespace metrics_test {

using namespace std::chrono_literals;

class MetricsTest : public ::testing::Test {
 protected:
  static EngineOptions Options(std::shared_ptr<ServerObserver> observer) {
    EngineOptions o;
    o.max_sessions = 4;
    o.observer = std::move(observer);
    return o;
  }
  static service::ServerOptions ServerOptions(std::shared_ptr<ServerObserver> observer) {
    service::ServerOptions o;
    o.service.observer = std::move(observer);
    return o;
  }

  void SetUp() override {
    ASSERT_TRUE(metrics_->Serve("127.0.0.1:0", engine_).ok());
    ASSERT_GT(metrics_->port(), 0);
  }
  void TearDown() override { metrics_->StopServing(); }

  std::vector<Sample> Scrape() {
    const HttpResponse response = HttpGet(metrics_->port(), "/metrics");
    EXPECT_EQ(response.status, 200);
    std::optional<std::vector<Sample>> samples = ParsePrometheusText(response.body);
    EXPECT_TRUE(samples.has_value()) << response.body;
    return samples.value_or(std::vector<Sample>{});
  }

  pb::Gistream::Stub& stub() { return server_.stub(); }

  std::unique_ptr<Stream> Open(grpc::ClientContext* context, const pb::SessionRequest& config,
                               pb::SessionOpened* opened) {
    auto stream = stub().Session(context);
    EXPECT_TRUE(stream->Write(config));
    pb::SessionEvent event;
    EXPECT_TRUE(stream->Read(&event));
    EXPECT_TRUE(event.has_opened()) << event.DebugString();
    *opened = event.opened();
    return stream;
  }

  pb::ServerStatus Status() {
    grpc::ClientContext context;
    SetDeadline(&context);
    pb::ServerStatus status;
    const grpc::Status rpc =
        stub().GetServerStatus(&context, pb::GetServerStatusRequest(), &status);
    EXPECT_TRUE(rpc.ok()) << rpc.error_message();
    return status;
  }

  // Declared in this order: the engine and server report to metrics_.
  std::shared_ptr<metrics::Metrics> metrics_ = std::make_shared<metrics::Metrics>();
  FakeEngine engine_{Options(metrics_)};
  TestServer server_{engine_, ServerOptions(metrics_)};
};

TEST_F(MetricsTest, ScrapeCountsFramesRejectionsAndFailedCallsByCodeName) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");

  // Three frames on request, one rejected update (unknown node: NOT_FOUND).
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::SessionOpened opened;
  auto stream = Open(&context, ConfigRequest(scene, 32, 16, /*on_request=*/true), &opened);
  ASSERT_TRUE(stream->Write(NodeUpdate(1, FakeEngine::kNodes + 5, 0.5f)));
  pb::SessionEvent event;
  ASSERT_TRUE(ReadNonFrame(*stream, &event));
  ASSERT_TRUE(event.has_rejected());
  // And an accepted one, which the frames below echo.
  ASSERT_TRUE(stream->Write(NodeUpdate(2, 0, 0.25f)));
  ASSERT_TRUE(stream->Write(FrameRequest(3)));
  uint64_t session_bytes = 0;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(stream->Read(&event));
    ASSERT_TRUE(event.has_frame());
    session_bytes += event.frame().image().size();
  }

  // One Render frame, and two failed calls.
  {
    grpc::ClientContext render_context;
    SetDeadline(&render_context);
    pb::RenderRequest request;
    request.set_scene_id(scene);
    request.set_width(8);
    request.set_height(8);
    pb::Frame frame;
    ASSERT_TRUE(stub().Render(&render_context, request, &frame).ok());
    session_bytes += frame.image().size();
  }
  {
    grpc::ClientContext load_context;
    SetDeadline(&load_context);
    pb::LoadSceneRequest request;
    request.set_name("no_such_scene");
    pb::LoadSceneResponse response;
    ASSERT_EQ(stub().LoadScene(&load_context, request, &response).error_code(),
              grpc::StatusCode::NOT_FOUND);
  }
  {
    grpc::ClientContext session_context;
    SetDeadline(&session_context);
    auto bad = stub().Session(&session_context);
    ASSERT_TRUE(bad->Write(ConfigRequest("no_such_scene-9", 8, 8, /*on_request=*/true)));
    bad->WritesDone();
    while (bad->Read(&event)) {
    }
    ASSERT_EQ(bad->Finish().error_code(), grpc::StatusCode::NOT_FOUND);
  }

  // Every frame above was counted before the client could read it.
  const std::vector<Sample> samples = Scrape();
  const double frames = 4.0;  // 3 session frames + 1 Render
  EXPECT_EQ(Sum(samples, "gistream_frames_rendered_total"), frames);
  EXPECT_EQ(Sum(samples, "gistream_frames_rendered_total", {{"solver", "direct"}}), frames);
  EXPECT_EQ(Sum(samples, "gistream_frames_rendered_total"),
            static_cast<double>(engine_.frames_rendered()));
  // Frame time histogram: a count per frame, +Inf bucket = count.
  EXPECT_EQ(Sum(samples, "gistream_frame_seconds_count", {{"solver", "direct"}}), frames);
  EXPECT_EQ(Sum(samples, "gistream_frame_seconds_bucket", {{"solver", "direct"}, {"le", "+Inf"}}),
            frames);
  // Stage histograms by solver and stage: the fake's shade (GPU) and encode
  // (CPU) run every frame; apply_updates is skipped (and not observed) in
  // frames that apply no update.
  EXPECT_EQ(Sum(samples, "gistream_stage_seconds_count",
                {{"solver", "direct"}, {"stage", "shade"}, {"where", "gpu"}}),
            frames);
  EXPECT_EQ(Sum(samples, "gistream_stage_seconds_count",
                {{"solver", "direct"}, {"stage", "encode"}, {"where", "cpu"}}),
            frames);
  // apply_updates ran for the frame that applied update 2 alone.
  EXPECT_EQ(Sum(samples, "gistream_stage_seconds_count", {{"stage", "apply_updates"}}), 1.0);

  EXPECT_EQ(Sum(samples, "gistream_updates_rejected_total", {{"code", "NOT_FOUND"}}), 1.0);
  EXPECT_EQ(Sum(samples, "gistream_updates_rejected_total"), 1.0);
  EXPECT_EQ(
      Sum(samples, "gistream_rpc_errors_total", {{"method", "LoadScene"}, {"code", "NOT_FOUND"}}),
      1.0);
  EXPECT_EQ(
      Sum(samples, "gistream_rpc_errors_total", {{"method", "Session"}, {"code", "NOT_FOUND"}}),
      1.0);
  EXPECT_EQ(Sum(samples, "gistream_rpc_errors_total"), 2.0);
  EXPECT_EQ(Sum(samples, "gistream_frames_dropped_total"), 0.0);
  // Every ended call by method and code, OK included (issue 31): the
  // LoadScene of the fixture's scene, the Render, the two failures; the
  // open session has not ended.
  EXPECT_EQ(Sum(samples, "gistream_requests_total", {{"method", "LoadScene"}, {"code", "OK"}}),
            1.0);
  EXPECT_EQ(Sum(samples, "gistream_requests_total", {{"method", "Render"}, {"code", "OK"}}), 1.0);
  EXPECT_EQ(
      Sum(samples, "gistream_requests_total", {{"method", "LoadScene"}, {"code", "NOT_FOUND"}}),
      1.0);
  EXPECT_EQ(Sum(samples, "gistream_requests_total", {{"method", "Session"}, {"code", "NOT_FOUND"}}),
            1.0);
  // The frames' bytes, as the client received them.
  EXPECT_GT(session_bytes, 0u);
  EXPECT_EQ(Sum(samples, "gistream_frame_bytes_sent_total"), double(session_bytes));
  // The accepted update was answered by the first frame (which echoes it);
  // the rejected one by its UpdateRejected, not counted.
  EXPECT_EQ(Sum(samples, "gistream_update_to_frame_seconds_count"), 1.0);
  // The open session by solver and state.
  EXPECT_EQ(Sum(samples, "gistream_sessions_by_state", {{"solver", "direct"}}), 1.0);

  // Gauges, read at the scrape.
  EXPECT_EQ(Sum(samples, "gistream_sessions"), 1.0);
  EXPECT_EQ(Sum(samples, "gistream_scenes"), 1.0);
  EXPECT_TRUE(Has(samples, "gistream_gl_object_bytes"));
  EXPECT_TRUE(Has(samples, "gistream_gpu_memory_total_bytes"));
  // Capacity: what an autoscaler reads (the fake engine reports no load).
  EXPECT_TRUE(Has(samples, "gistream_render_busy_ratio"));
  EXPECT_TRUE(Has(samples, "gistream_render_busy_limit"));
  EXPECT_TRUE(Has(samples, "gistream_active_sessions"));
  EXPECT_GT(Sum(samples, "process_resident_memory_bytes"), 0.0);
  EXPECT_TRUE(Has(samples, "gistream_build_info", {{"version", std::string(Version())}}));

  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
}

TEST_F(MetricsTest, DroppedFramesAreCountedInMetricsAndSessionStatus) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::SessionOpened opened;
  // Big frames at 240 fps that the test does not read: the service replaces
  // unsent frames and counts them.
  auto stream =
      Open(&context, ConfigRequest(scene, 256, 256, /*on_request=*/false, 240.0f), &opened);
  uint64_t status_dropped = 0;
  ASSERT_TRUE(WaitFor([&] {
    for (const SessionStatus& s : engine_.stats().session_status) {
      if (s.id == opened.session_id()) status_dropped = s.dropped_frames;
    }
    return status_dropped > 0;
  }));
  // Counters only grow: the scrape comes after the status read.
  const std::vector<Sample> samples = Scrape();
  EXPECT_GE(Sum(samples, "gistream_frames_dropped_total"), static_cast<double>(status_dropped));

  const pb::ServerStatus status = Status();
  ASSERT_EQ(status.session_status_size(), 1);
  EXPECT_GE(status.session_status(0).dropped_frames(), status_dropped);
  context.TryCancel();
  stream->Finish();
}

TEST_F(MetricsTest, EndpointAnswersOnlyMetricsPath) {
  EXPECT_EQ(HttpGet(metrics_->port(), "/metrics").status, 200);
  EXPECT_EQ(HttpGet(metrics_->port(), "/nope").status, 404);
}

// Issue 30: the endpoint behind a token (HTTP Basic, the token as the
// password): 401 without it or with another, 200 with it.
TEST_F(MetricsTest, ATokenGuardsTheEndpoint) {
  metrics::Metrics guarded;
  ASSERT_TRUE(guarded.Serve("127.0.0.1:0", engine_, "s3cret-token").ok());
  auto basic = [](const std::string& in) {  // "Authorization: Basic base64(in)"
    static const char* kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    auto byte = [&](size_t i) { return i < in.size() ? uint32_t(uint8_t(in[i])) : 0u; };
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
      const uint32_t v = byte(i) << 16 | byte(i + 1) << 8 | byte(i + 2);
      const size_t chars = std::min<size_t>(in.size() - i, 3) + 1;  // 2, 3 or 4
      for (size_t k = 0; k < 4; ++k) out += k < chars ? kAlphabet[(v >> (18 - 6 * k)) & 63] : '=';
    }
    return "Authorization: Basic " + out + "\r\n";
  };
  EXPECT_EQ(HttpGet(guarded.port(), "/metrics").status, 401);
  EXPECT_EQ(HttpGet(guarded.port(), "/metrics", basic("prometheus:wrong-token")).status, 401);
  EXPECT_EQ(HttpGet(guarded.port(), "/metrics", basic("prometheus:s3cret-token")).status, 200);
  guarded.StopServing();
  // Without a token the endpoint is open (the fixture's).
  EXPECT_EQ(HttpGet(metrics_->port(), "/metrics").status, 200);
}

TEST_F(MetricsTest, ServeOnABusyPortIsUnavailable) {
  metrics::Metrics second;
  const absl::Status status = second.Serve(absl::StrCat("127.0.0.1:", metrics_->port()), engine_);
  EXPECT_EQ(status.code(), absl::StatusCode::kUnavailable) << status;
  EXPECT_TRUE(absl::StrContains(status.message(), "--metrics-listen")) << status;
}

// ---------------------------------------------------------------- status

TEST_F(MetricsTest, ServerStatusReportsVersionProcessAndSessions) {
  const std::string scene = LoadSceneOrDie(stub(), "cornell_box");
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::SessionOpened opened;
  auto stream = Open(&context, ConfigRequest(scene, 48, 32, /*on_request=*/true), &opened);
  ASSERT_TRUE(stream->Write(NodeUpdate(7, 1, 0.25f)));
  ASSERT_TRUE(stream->Write(FrameRequest(2)));
  pb::SessionEvent event;
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(stream->Read(&event));
    ASSERT_TRUE(event.has_frame());
  }

  const pb::ServerStatus status = Status();
  EXPECT_EQ(status.version(), std::string(Version()));
  EXPECT_FALSE(status.version().empty());
  EXPECT_GT(status.uptime_s(), 0.0);
  EXPECT_GT(status.rss_bytes(), 0u);
  EXPECT_GE(status.peak_rss_bytes(), status.rss_bytes());
  EXPECT_GT(status.cpu_seconds(), 0.0);
  EXPECT_EQ(status.sessions(), 1u);
  ASSERT_EQ(status.session_status_size(), 1);
  const pb::SessionStatus& s = status.session_status(0);
  EXPECT_EQ(s.session_id(), opened.session_id());
  EXPECT_EQ(s.scene_id(), scene);
  EXPECT_EQ(s.solver(), "direct");
  EXPECT_EQ(s.width(), 48u);
  EXPECT_EQ(s.height(), 32u);
  EXPECT_EQ(s.frames(), 2u);
  EXPECT_GE(s.fps(), 0.0);  // its arithmetic: tests/unit/frame_rate_test.cpp (no clock here)
  EXPECT_EQ(s.last_update_seq(), 7u);
  EXPECT_EQ(s.pending_updates(), 0u);
  EXPECT_EQ(s.dropped_frames(), 0u);
  // The fake engine holds no GL objects and its driver tells nothing.
  EXPECT_EQ(status.gpu_memory_total_bytes(), 0u);

  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
}

}  // namespace metrics_test
}  // namespace gistream::testing
