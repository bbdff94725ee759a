#include "backend_health.h"

#include <condition_variable>
#include <stop_token>

#include "grpc/health/v1/health.grpc.pb.h"
#include "util/log.h"

namespace gistream::web {

BackendHealth::BackendHealth(std::shared_ptr<grpc::Channel> channel, std::string address,
                             std::chrono::milliseconds period)
    : channel_(std::move(channel)), address_(std::move(address)) {
  state_.detail = "not checked yet";
  thread_ = std::jthread([this, period](std::stop_token stop) {
    std::mutex wait_mutex;
    std::condition_variable_any wake;
    while (!stop.stop_requested()) {
      Check();
      std::unique_lock lock(wait_mutex);
      wake.wait_for(lock, stop, period, [] { return false; });
    }
  });
}

BackendHealth::~BackendHealth() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void BackendHealth::Check() {
  auto stub = grpc::health::v1::Health::NewStub(channel_);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(1));
  grpc::health::v1::HealthCheckRequest request;  // "": the whole server
  grpc::health::v1::HealthCheckResponse response;
  const grpc::Status status = stub->Check(&context, request, &response);
  State next;
  if (!status.ok()) {
    next.detail = status.error_message().empty() ? "unreachable" : status.error_message();
  } else {
    next.serving = response.status() == grpc::health::v1::HealthCheckResponse::SERVING;
    next.detail = grpc::health::v1::HealthCheckResponse::ServingStatus_Name(response.status());
  }
  std::lock_guard lock(mutex_);
  if (next.serving != state_.serving || state_.detail == "not checked yet") {
    Log(next.serving ? LogLevel::kInfo : LogLevel::kWarning,
        "backend " + address_ + (next.serving ? " serving" : " not serving: " + next.detail));
  }
  state_ = std::move(next);
}

BackendHealth::State BackendHealth::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

}  // namespace gistream::web
