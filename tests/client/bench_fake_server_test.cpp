// gistream bench end to end against in-process fake servers on loopback:
// every update sent is answered by the frame that echoes its seq, the
// step arithmetic holds (answered + rejected + unanswered = sent, ordered
// percentiles), sessions spread round-robin over servers, the interferer
// renders on its own, and every output file is written. No wall-clock
// thresholds: the fakes answer as fast as they can.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "gistream/v1/gistream.grpc.pb.h"

namespace gistream::client {
namespace bench_fake_server_test {

namespace fs = std::filesystem;

// Streams a frame every 2 ms that echoes the last update seq it has read.
class FakeServer final : public v1::Gistream::Service {
 public:
  explicit FakeServer(uint64_t rss) : rss_(rss) {}

  grpc::Status LoadScene(grpc::ServerContext*, const v1::LoadSceneRequest*,
                         v1::LoadSceneResponse* response) override {
    response->set_scene_id("scene-1");
    response->mutable_bounds()->mutable_max()->set_x(1);
    response->mutable_bounds()->mutable_max()->set_y(1);
    response->mutable_bounds()->mutable_max()->set_z(1);
    auto* block = response->add_nodes();
    block->set_id(6);
    block->set_name("tall_block");
    block->set_mesh(6);
    return grpc::Status::OK;
  }
  grpc::Status UnloadScene(grpc::ServerContext*, const v1::UnloadSceneRequest*,
                           v1::UnloadSceneResponse*) override {
    return grpc::Status::OK;
  }
  grpc::Status GetServerStatus(grpc::ServerContext*, const v1::GetServerStatusRequest*,
                               v1::ServerStatus* status) override {
    const int call = ++status_calls_;
    status->set_gl_renderer("fake");
    status->set_version("0.0-test");
    status->set_rss_bytes(rss_);
    status->set_uptime_s(call);           // one "second" per call ...
    status->set_cpu_seconds(0.5 * call);  // ... half of it on the CPU: 50 %
    return grpc::Status::OK;
  }
  grpc::Status Render(grpc::ServerContext*, const v1::RenderRequest* request,
                      v1::Frame* frame) override {
    {
      std::lock_guard lock(mutex_);
      renders.push_back(*request);
    }
    frame->set_frame_number(1);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return grpc::Status::OK;
  }

  grpc::Status Session(
      grpc::ServerContext* context,
      grpc::ServerReaderWriter<v1::SessionEvent, v1::SessionRequest>* stream) override {
    v1::SessionRequest request;
    if (!stream->Read(&request) || !request.has_config()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "config: must come first");
    }
    sessions_opened++;
    v1::SessionEvent opened;
    opened.mutable_opened()->set_session_id("s");
    stream->Write(opened);
    std::atomic<uint64_t> last_seq{0};
    std::atomic<bool> half_closed{false};
    std::thread reader([&] {
      v1::SessionRequest in;
      while (stream->Read(&in)) {
        if (!in.has_update()) continue;
        {
          std::lock_guard lock(mutex_);
          updates.push_back(in.update());
        }
        last_seq = in.update().seq();
      }
      half_closed = true;
    });
    uint64_t number = 0;
    while (!context->IsCancelled() && !half_closed) {
      v1::SessionEvent event;
      v1::Frame* frame = event.mutable_frame();
      frame->set_frame_number(++number);
      frame->set_last_update_seq(last_seq);
      frame->set_image("0123456789");  // 10 bytes
      frame->set_total_ms(1.0);
      auto* timing = frame->add_timings();
      timing->set_name("shade");
      timing->set_gpu_ms(0.5);
      if (!stream->Write(event)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    reader.join();
    return grpc::Status::OK;
  }

  std::mutex mutex_;
  std::vector<v1::Update> updates;
  std::vector<v1::RenderRequest> renders;
  std::atomic<int> sessions_opened{0};

 private:
  uint64_t rss_;
  std::atomic<int> status_calls_{0};
};

struct RunningFake {
  explicit RunningFake(uint64_t rss) : service(rss) {
    grpc::ServerBuilder builder;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
    builder.RegisterService(&service);
    server = builder.BuildAndStart();
  }
  ~RunningFake() { server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(2)); }
  std::string address() const { return "127.0.0.1:" + std::to_string(port); }

  FakeServer service;
  int port = 0;
  std::unique_ptr<grpc::Server> server;
};

class BenchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("gistream_bench_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  BenchOptions Options() const {
    BenchOptions options;
    options.scene.scene = "cornell_box";
    options.view.width = 16;
    options.view.height = 16;
    options.workload = "object";
    options.sessions = {1, 2};
    options.duration_s = 0.3;
    options.warmup_s = 0.05;
    options.fps = 0.0f;
    options.out_dir = dir_;
    return options;
  }

  nlohmann::json Results() const {
    std::ifstream in(dir_ / "results.json");
    return nlohmann::json::parse(in);
  }

  fs::path dir_;
};

// Every step's counts add up and its percentiles are ordered.
void ExpectConsistentStep(const nlohmann::json& step) {
  const uint64_t sent = step["updates_sent"];
  EXPECT_GT(sent, 0u);
  EXPECT_EQ(uint64_t(step["updates_answered"]) + uint64_t(step["updates_rejected"]) +
                uint64_t(step["updates_unanswered"]),
            sent);
  const auto& lat = step["latency_ms"];
  ASSERT_FALSE(lat["p50"].is_null());
  EXPECT_GE(double(lat["p50"]), 0.0);
  EXPECT_LE(double(lat["p50"]), double(lat["p95"]));
  EXPECT_LE(double(lat["p95"]), double(lat["p99"]));
  EXPECT_LE(double(lat["p99"]), double(lat["max"]));
  EXPECT_GT(uint64_t(step["frames"]), 0u);
  EXPECT_GT(double(step["jain_fairness"]), 0.0);
  EXPECT_LE(double(step["jain_fairness"]), 1.0 + 1e-12);
  EXPECT_EQ(step["per_session"].size(), size_t(step["sessions"]));
  // Bytes per second is the 10-byte frames over the window.
  EXPECT_DOUBLE_EQ(double(step["bytes_per_s"]), 10.0 * double(step["frames"]) / 0.3);
  EXPECT_EQ(step["stages"][0]["name"], "shade");
}

TEST_F(BenchTest, ClosedLoopStepsMatchEveryUpdateAndWriteEveryFile) {
  RunningFake fake(123456789);
  ConnectionOptions connection;
  connection.server = fake.address();
  connection.timeout_seconds = 10;
  ASSERT_TRUE(RunBench(connection, Options()).ok());

  const nlohmann::json doc = Results();
  ASSERT_EQ(doc["steps"].size(), 2u);
  EXPECT_EQ(doc["steps"][0]["sessions"], 1);
  EXPECT_EQ(doc["steps"][1]["sessions"], 2);
  for (const auto& step : doc["steps"]) {
    ExpectConsistentStep(step);
    // The fake frames every update straight back: none is left unanswered,
    // and every session settles (its frames carry no update_complete stat).
    EXPECT_EQ(step["updates_unanswered"], 0);
    EXPECT_EQ(step["unsettled_sessions"], 0);
    EXPECT_GE(double(step["settle_ms"]["p50"]), 0.0);
    ASSERT_EQ(step["servers"].size(), 1u);
    EXPECT_EQ(step["servers"][0]["max_rss_bytes"], 123456789u);
    // uptime advances 1 and CPU time 0.5 per status call: 50 %.
    EXPECT_DOUBLE_EQ(double(step["servers"][0]["cpu_percent"]), 50.0);
  }
  EXPECT_EQ(doc["workload"], "object");
  EXPECT_EQ(fake.service.sessions_opened, 3);
  {
    // The object workload moved the block; seqs rise within each session.
    std::lock_guard lock(fake.service.mutex_);
    ASSERT_FALSE(fake.service.updates.empty());
    for (const v1::Update& u : fake.service.updates) {
      ASSERT_TRUE(u.has_node_transform());
      EXPECT_EQ(u.node_transform().node(), 6u);
    }
  }
  for (const char* name : {"results.csv", "results.md", "latency_cdf.png", "fps_vs_sessions.png",
                           "latency_vs_sessions.png"}) {
    std::ifstream in(dir_ / name, std::ios::binary);
    ASSERT_TRUE(in) << name;
    std::string head(8, '\0');
    in.read(head.data(), 8);
    if (fs::path(name).extension() == ".png") {
      EXPECT_EQ(head.substr(1, 3), "PNG") << name;
    }
  }
  std::ifstream csv(dir_ / "results.csv");
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 3);  // header + one row per step
}

TEST_F(BenchTest, OpenLoopSessionsSpreadOverServersBesideAnInterferer) {
  RunningFake a(1 << 20), b(2 << 20);
  ConnectionOptions connection;
  connection.server = a.address() + "," + b.address();
  connection.timeout_seconds = 10;
  BenchOptions options = Options();
  options.sessions = {3};
  options.update_hz = 200.0;
  options.channel_per_session = true;
  options.interfere = "render --solver pathtrace --param spp=4 --size 8x8";
  ASSERT_TRUE(RunBench(connection, options).ok());

  const nlohmann::json step = Results()["steps"][0];
  ExpectConsistentStep(step);
  // Round-robin: sessions 1 and 3 on a, session 2 on b.
  EXPECT_EQ(a.service.sessions_opened, 2);
  EXPECT_EQ(b.service.sessions_opened, 1);
  std::multiset<std::string> placed;
  for (const auto& s : step["per_session"]) placed.insert(std::string(s["server"]));
  EXPECT_EQ(placed.count(a.address()), 2u);
  EXPECT_EQ(placed.count(b.address()), 1u);
  EXPECT_EQ(step["servers"].size(), 2u);
  // The interferer rendered what --interfere said, on the first server only.
  std::lock_guard lock(a.service.mutex_);
  ASSERT_FALSE(a.service.renders.empty());
  EXPECT_EQ(a.service.renders[0].solver(), "pathtrace");
  EXPECT_EQ(a.service.renders[0].params().at("spp"), "4");
  EXPECT_EQ(a.service.renders[0].width(), 8u);
  EXPECT_EQ(a.service.renders[0].scene_id(), "scene-1");
  EXPECT_TRUE(b.service.renders.empty());
  // Finished renders: all it sent but the one cancelled at the step's end.
  EXPECT_LE(int(step["interferer"]["renders"]), int(a.service.renders.size()));
  EXPECT_GE(int(step["interferer"]["renders"]), int(a.service.renders.size()) - 1);
}

TEST_F(BenchTest, AWorkloadTheSceneCannotRunIsAnError) {
  RunningFake fake(1);
  ConnectionOptions connection;
  connection.server = fake.address();
  BenchOptions options = Options();
  options.workload = "light";  // the fake scene has no light and no emitter
  const absl::Status status = RunBench(connection, options);
  EXPECT_EQ(status.code(), absl::StatusCode::kFailedPrecondition) << status;
  EXPECT_EQ(fake.service.sessions_opened, 0);
}

}  // namespace bench_fake_server_test
}  // namespace gistream::client
