// An in-process gistream server on 127.0.0.1:<free port> for service tests,
// plus small client helpers.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <grpcpp/grpcpp.h>

#include "gistream/v1/gistream.grpc.pb.h"
#include "grpc/health/v1/health.grpc.pb.h"
#include "engine/engine.h"
#include "service/server.h"

namespace gistream::testing {

namespace pb = ::gistream::v1;
using Stream = grpc::ClientReaderWriter<pb::SessionRequest, pb::SessionEvent>;

// Every blocking client call in the tests gets this deadline, so a bug
// fails a test instead of hanging it.
inline constexpr std::chrono::seconds kCallTimeout{20};

inline void SetDeadline(grpc::ClientContext* context,
                        std::chrono::milliseconds timeout = kCallTimeout) {
  context->set_deadline(std::chrono::system_clock::now() + timeout);
}

// Serves `engine` (not owned; must outlive this) on a free loopback port.
class TestServer {
 public:
  explicit TestServer(Engine& engine, service::ServerOptions options = {}) {
    options.listen = "127.0.0.1:0";
    auto server = service::GistreamServer::Start(engine, options);
    EXPECT_TRUE(server.ok()) << server.status();
    if (server.ok()) server_ = *std::move(server);
    channel_ = grpc::CreateChannel(address(), grpc::InsecureChannelCredentials());
    stub_ = pb::Gistream::NewStub(channel_);
    health_ = ::grpc::health::v1::Health::NewStub(channel_);
  }

  std::string address() const { return server_ ? server_->address() : "127.0.0.1:1"; }
  service::GistreamServer& server() { return *server_; }
  pb::Gistream::Stub& stub() { return *stub_; }
  ::grpc::health::v1::Health::Stub& health() { return *health_; }
  std::shared_ptr<grpc::Channel> channel() { return channel_; }

 private:
  std::unique_ptr<service::GistreamServer> server_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<pb::Gistream::Stub> stub_;
  std::unique_ptr<::grpc::health::v1::Health::Stub> health_;
};

// Polls `pred` every 10 ms until it holds or `timeout` passes.
template <typename Pred>
bool WaitFor(Pred pred, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return pred();
}

inline std::string LoadSceneOrDie(pb::Gistream::Stub& stub, const std::string& name) {
  grpc::ClientContext context;
  SetDeadline(&context);
  pb::LoadSceneRequest request;
  request.set_name(name);
  pb::LoadSceneResponse response;
  const grpc::Status status = stub.LoadScene(&context, request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return response.scene_id();
}

inline pb::SessionRequest ConfigRequest(const std::string& scene, uint32_t width, uint32_t height,
                                        bool on_request, float max_fps = 0.0f) {
  pb::SessionRequest request;
  pb::SessionConfig* config = request.mutable_config();
  config->set_scene_id(scene);
  config->set_width(width);
  config->set_height(height);
  if (on_request) {
    config->mutable_on_request();
  } else {
    config->mutable_continuous()->set_max_fps(max_fps);
  }
  return request;
}

inline pb::SessionRequest NodeUpdate(uint64_t seq, uint32_t node, float x) {
  pb::SessionRequest request;
  pb::Update* update = request.mutable_update();
  update->set_seq(seq);
  pb::NodeTransform* t = update->mutable_node_transform();
  t->set_node(node);
  t->mutable_translation()->set_x(x);
  return request;
}

inline pb::SessionRequest FrameRequest(uint32_t count) {
  pb::SessionRequest request;
  request.mutable_request_frame()->set_count(count);
  return request;
}

// Reads events until one that is not a frame (or the stream ends).
inline bool ReadNonFrame(Stream& stream, pb::SessionEvent* event) {
  while (stream.Read(event)) {
    if (!event->has_frame()) return true;
  }
  return false;
}

}  // namespace gistream::testing
