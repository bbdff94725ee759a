// The network paths of render, stream and script against an in-process fake
// gistreamd on loopback: files written, seq numbers sent in order, echo
// checked, half-close, unload, and server errors passed through.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <absl/strings/match.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include "commands.h"
#include "connection.h"
#include "gistream/v1/gistream.grpc.pb.h"

namespace gistream::client {
namespace commands_fake_server_test {

namespace fs = std::filesystem;

// What a test wants the fake to do wrong.
enum class Fault { kNone, kRejectSecondUpdate, kEchoTooHigh, kIgnoreHalfClose, kDrainingLoads };

class FakeGistream final : public v1::Gistream::Service {
 public:
  Fault fault = Fault::kNone;
  int draining_loads = 0;  // kDrainingLoads: how many loads are refused

  grpc::Status LoadScene(grpc::ServerContext*, const v1::LoadSceneRequest* request_ptr,
                         v1::LoadSceneResponse* response) override {
    std::lock_guard lock(mutex_);
    load_requests.push_back(*request_ptr);
    // A server that drains, its balancer still routing this connection to
    // it: the first `draining_loads` loads are refused as gistreamd does.
    if (fault == Fault::kDrainingLoads && int(load_requests.size()) <= draining_loads) {
      return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                          "the server is draining: load the scene elsewhere");
    }
    response->set_scene_id("scene-1");
    auto* node = response->add_nodes();
    node->set_id(4);
    node->set_name("light");
    node->mutable_scale()->set_x(1);
    node->mutable_scale()->set_y(1);
    node->mutable_scale()->set_z(1);
    return grpc::Status::OK;
  }

  grpc::Status UnloadScene(grpc::ServerContext*, const v1::UnloadSceneRequest* request_ptr,
                           v1::UnloadSceneResponse*) override {
    std::lock_guard lock(mutex_);
    unloaded.push_back(request_ptr->scene_id());
    return grpc::Status::OK;
  }

  grpc::Status Render(grpc::ServerContext*, const v1::RenderRequest* request_ptr,
                      v1::Frame* frame) override {
    const v1::RenderRequest& request = *request_ptr;
    if (request.params().count("area_samples") && request.params().at("area_samples") == "0") {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "params.area_samples: 0 is out of range [1, 1024]");
    }
    *frame = MakeFrame(1, 0);
    frame->set_width(request.width());
    frame->set_height(request.height());
    frame->set_format(request.encoding().format());
    return grpc::Status::OK;
  }

  grpc::Status Session(
      grpc::ServerContext* context,
      grpc::ServerReaderWriter<v1::SessionEvent, v1::SessionRequest>* stream) override {
    v1::SessionRequest request;
    if (!stream->Read(&request) || !request.has_config()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "config: must come first");
    }
    const v1::SessionConfig config = request.config();
    if (config.width() == 0) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "config.width: 0 is out of range");
    }
    v1::SessionEvent opened;
    opened.mutable_opened()->set_session_id("session-1");
    opened.mutable_opened()->set_scene_id(config.scene_id());
    opened.mutable_opened()->set_solver("direct");
    (*opened.mutable_opened()->mutable_params())["area_samples"] = "16";
    stream->Write(opened);
    return config.has_continuous() ? Continuous(context, stream) : OnRequest(stream);
  }

  std::mutex mutex_;
  std::vector<v1::LoadSceneRequest> load_requests;
  std::vector<std::string> unloaded;
  std::vector<v1::Update> updates;  // in arrival order
  std::atomic<bool> half_closed{false};

 private:
  static v1::Frame MakeFrame(uint64_t number, uint64_t seq) {
    v1::Frame frame;
    frame.set_frame_number(number);
    frame.set_image("IMAGE" + std::to_string(number));
    frame.set_last_update_seq(seq);
    frame.set_total_ms(2.0);
    auto* timing = frame.add_timings();
    timing->set_name("shade");
    timing->set_gpu_ms(1.0);
    return frame;
  }

  grpc::Status OnRequest(grpc::ServerReaderWriter<v1::SessionEvent, v1::SessionRequest>* stream) {
    uint64_t last_seq = 0;
    uint64_t frame_number = 0;
    int update_count = 0;
    v1::SessionRequest request;
    while (stream->Read(&request)) {
      if (request.has_update()) {
        {
          std::lock_guard lock(mutex_);
          updates.push_back(request.update());
        }
        if (fault == Fault::kRejectSecondUpdate && ++update_count == 2) {
          v1::SessionEvent event;
          event.mutable_rejected()->set_seq(request.update().seq());
          event.mutable_rejected()->set_code(grpc::StatusCode::NOT_FOUND);
          event.mutable_rejected()->set_message("node_transform.node: no node 4");
          stream->Write(event);
          continue;
        }
        last_seq = request.update().seq();
      } else if (request.has_request_frame()) {
        v1::SessionEvent event;
        *event.mutable_frame() =
            MakeFrame(++frame_number, fault == Fault::kEchoTooHigh ? last_seq + 1 : last_seq);
        stream->Write(event);
      }
    }
    half_closed = true;
    return grpc::Status::OK;
  }

  grpc::Status Continuous(grpc::ServerContext* context,
                          grpc::ServerReaderWriter<v1::SessionEvent, v1::SessionRequest>* stream) {
    std::thread reader([&] {
      v1::SessionRequest ignored;
      while (stream->Read(&ignored)) {
      }
      half_closed = true;
    });
    uint64_t frame_number = 0;
    while (!context->IsCancelled() && (!half_closed || fault == Fault::kIgnoreHalfClose)) {
      v1::SessionEvent event;
      *event.mutable_frame() = MakeFrame(++frame_number, 0);
      if (!stream->Write(event)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    reader.join();
    return grpc::Status::OK;
  }
};

class CommandsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    grpc::ServerBuilder builder;
    int port = 0;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
    builder.RegisterService(&service_);
    server_ = builder.BuildAndStart();
    ASSERT_NE(port, 0);
    connection_.server = "127.0.0.1:" + std::to_string(port);
    connection_.timeout_seconds = 10;
    dir_ = fs::temp_directory_path() /
           ("gistream_commands_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override {
    server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(2));
    fs::remove_all(dir_);
  }

  std::string ReadAll(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  fs::path WriteScript(const std::string& text) {
    const fs::path path = dir_ / "script.json";
    std::ofstream(path) << text;
    return path;
  }

  FakeGistream service_;
  std::unique_ptr<grpc::Server> server_;
  ConnectionOptions connection_;
  fs::path dir_;
};

TEST_F(CommandsTest, RenderWritesTheImageAndUnloads) {
  RenderOptions options;
  options.scene.scene = "cornell_box";
  options.view.encoding.set_format(v1::IMAGE_FORMAT_PNG);
  options.out = dir_ / "sub" / "shot.png";
  ASSERT_TRUE(RunRender(connection_, options).ok());
  EXPECT_EQ(ReadAll(options.out), "IMAGE1");
  ASSERT_EQ(service_.load_requests.size(), 1u);
  EXPECT_EQ(service_.load_requests[0].name(), "cornell_box");
  EXPECT_EQ(service_.unloaded, std::vector<std::string>{"scene-1"});
}

TEST_F(CommandsTest, ALoadADrainingServerRefusesIsTriedAgain) {
  // Two refusals, then a server that takes it (a fresh connection each
  // time, which a balancer routes anew): render, stream and script load
  // through ConnectAndLoad.
  service_.fault = Fault::kDrainingLoads;
  service_.draining_loads = 2;
  RenderOptions options;
  options.scene.scene = "cornell_box";
  options.out = dir_ / "shot.jpg";
  ASSERT_TRUE(RunRender(connection_, options).ok());
  EXPECT_EQ(service_.load_requests.size(), 3u);
  EXPECT_EQ(ReadAll(options.out), "IMAGE1");
  // With no time to try again (stream --resume-for 0), the refusal is the
  // answer, code and message kept.
  service_.load_requests.clear();
  StreamOptions stream;
  stream.scene.scene = "cornell_box";
  stream.frames = 1;
  stream.out_dir = dir_ / "frames";
  stream.resume_for_s = 0.0f;
  const absl::Status status = RunStream(connection_, stream);
  EXPECT_TRUE(absl::IsUnavailable(status)) << status;
  EXPECT_TRUE(absl::StrContains(status.message(), "draining")) << status;
  EXPECT_EQ(service_.load_requests.size(), 1u);
}

TEST_F(CommandsTest, ServerErrorKeepsCodeAndMessage) {
  RenderOptions options;
  options.scene.scene = "cornell_box";
  options.solver.params["area_samples"] = "0";
  options.out = dir_ / "shot.jpg";
  const absl::Status status = RunRender(connection_, options);
  EXPECT_TRUE(absl::IsInvalidArgument(status));
  EXPECT_TRUE(IsRpcError(status));
  EXPECT_EQ(status.message(), "params.area_samples: 0 is out of range [1, 1024]");
  EXPECT_FALSE(fs::exists(options.out));
}

TEST_F(CommandsTest, InvalidSessionConfigIsTheCallStatus) {
  StreamOptions options;
  options.scene.scene = "cornell_box";
  options.view.width = 0;
  options.out_dir = dir_;
  const absl::Status status = RunStream(connection_, options);
  EXPECT_TRUE(absl::IsInvalidArgument(status)) << status;
  EXPECT_EQ(status.message(), "config.width: 0 is out of range");
}

TEST_F(CommandsTest, StreamSavesFramesAndHalfCloses) {
  StreamOptions options;
  options.scene.scene = "cornell_box";
  options.frames = 5;
  options.out_dir = dir_ / "frames";
  ASSERT_TRUE(RunStream(connection_, options).ok());
  for (int i = 0; i < 5; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.jpg", i);
    EXPECT_EQ(ReadAll(options.out_dir / name), "IMAGE" + std::to_string(i + 1));
  }
  EXPECT_FALSE(fs::exists(options.out_dir / "frame_00005.jpg"));
  EXPECT_TRUE(service_.half_closed);
}

TEST_F(CommandsTest, StreamCancelsAServerThatIgnoresTheHalfClose) {
  service_.fault = Fault::kIgnoreHalfClose;
  StreamOptions options;
  options.scene.scene = "cornell_box";
  options.frames = 2;
  options.out_dir = dir_;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(RunStream(connection_, options).ok());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(9));
}

TEST_F(CommandsTest, ScriptSendsIncreasingSeqAndSavesOneFramePerStep) {
  ScriptOptions options;
  options.file = WriteScript(R"({"scene": "cornell_box", "frames": 4, "format": "png",
      "tracks": [{"type": "node_path", "node": "light", "keys": [
          {"frame": 0, "translation": [0, 0, 0]}, {"frame": 2, "translation": [0, 1, 0]}]}],
      "events": [{"frame": 3, "update": {"environment": {"intensity": 2}}}]})");
  options.out_dir = dir_ / "out";
  ASSERT_TRUE(RunScript(connection_, options).ok());
  for (int i = 0; i < 4; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", i);
    EXPECT_EQ(ReadAll(options.out_dir / name), "IMAGE" + std::to_string(i + 1)) << name;
  }
  // Frames 0..2 move the node, frame 3 holds it and sends the event.
  ASSERT_EQ(service_.updates.size(), 4u);
  for (size_t i = 0; i < service_.updates.size(); ++i) {
    EXPECT_EQ(service_.updates[i].seq(), i + 1);
  }
  EXPECT_EQ(service_.updates[0].node_transform().node(), 4u);
  EXPECT_FLOAT_EQ(service_.updates[1].node_transform().translation().y(), 0.5f);
  EXPECT_TRUE(service_.updates[3].has_environment());
  EXPECT_TRUE(service_.half_closed);
  EXPECT_EQ(service_.unloaded, std::vector<std::string>{"scene-1"});
}

TEST_F(CommandsTest, ScriptStopsOnARejectedUpdate) {
  service_.fault = Fault::kRejectSecondUpdate;
  ScriptOptions options;
  options.file = WriteScript(R"({"scene": "cornell_box", "frames": 3, "tracks": [
      {"type": "node_spin", "node": "light", "degrees_per_frame": 10}]})");
  options.out_dir = dir_;
  const absl::Status status = RunScript(connection_, options);
  EXPECT_TRUE(absl::IsInvalidArgument(status)) << status;
  EXPECT_EQ(status.message(),
            "frame 1: update seq 2 (node_transform (node 4)) rejected: NOT_FOUND: "
            "node_transform.node: no node 4");
}

TEST_F(CommandsTest, ScriptChecksTheSeqEcho) {
  service_.fault = Fault::kEchoTooHigh;
  ScriptOptions options;
  options.file = WriteScript(R"({"scene": "cornell_box", "frames": 2})");
  options.out_dir = dir_;
  const absl::Status status = RunScript(connection_, options);
  EXPECT_TRUE(absl::IsDataLoss(status)) << status;
  EXPECT_EQ(status.message(), "frame 1 reports update seq 1 but the client has sent only up to 0");
}

TEST_F(CommandsTest, ScriptUnknownNodeFailsBeforeTheSession) {
  ScriptOptions options;
  options.file = WriteScript(R"({"scene": "cornell_box", "frames": 2, "tracks": [
      {"type": "node_spin", "node": "lamp", "degrees_per_frame": 10}]})");
  options.out_dir = dir_;
  const absl::Status status = RunScript(connection_, options);
  EXPECT_TRUE(absl::IsInvalidArgument(status));
  EXPECT_EQ(status.message(), options.file.string() +
                                  ": tracks[0].node: the scene has no node named \"lamp\" "
                                  "(nodes: light)");
  EXPECT_TRUE(service_.updates.empty());
}

}  // namespace commands_fake_server_test
}  // namespace gistream::client
