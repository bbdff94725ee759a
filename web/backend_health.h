// gistream-web's view of its gistreamd (issue 31): a thread asks the
// backend's grpc.health.v1 Check every period (one-second deadline) and
// keeps the answer, so /healthz says whether browsers can be served now: a
// backend that restarted, drains (NOT_SERVING) or is gone turns the
// gateway's /healthz to 503 within one period, naming why.
#pragma once

#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <grpcpp/grpcpp.h>

namespace gistream::web {

class BackendHealth {
 public:
  struct State {
    bool serving = false;
    std::string detail;  // "SERVING", "NOT_SERVING", or the call's error
  };

  // Starts polling `channel` (the backend at `address`, for messages).
  BackendHealth(std::shared_ptr<grpc::Channel> channel, std::string address,
                std::chrono::milliseconds period = std::chrono::seconds(2));
  ~BackendHealth();  // stops the thread
  BackendHealth(const BackendHealth&) = delete;
  BackendHealth& operator=(const BackendHealth&) = delete;

  State state() const;
  const std::string& address() const { return address_; }

 private:
  void Check();

  std::shared_ptr<grpc::Channel> channel_;
  const std::string address_;
  mutable std::mutex mutex_;
  State state_;
  std::jthread thread_;
};

}  // namespace gistream::web
