// The Prometheus endpoint (`gistreamd --metrics-listen ADDR`): a
// ServerObserver that counts what the engine and the gRPC layer report
// (frames and their stage times, dropped frames, rejected updates, failed
// calls by code), plus gauges read from Engine::stats() and the process at
// each scrape. The only module that includes prometheus-cpp; its types stay
// behind this header. Metric names: see README "Monitoring".
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "engine/engine.h"
#include "engine/observer.h"
#include "util/status.h"

namespace gistream::metrics {

class Metrics final : public ServerObserver {
 public:
  Metrics();
  ~Metrics() override;
  Metrics(const Metrics&) = delete;
  Metrics& operator=(const Metrics&) = delete;

  void OnFrameRendered(const EncodedFrame& frame) override;
  void OnFramesDropped(uint64_t count) override;
  void OnUpdateRejected(absl::StatusCode code) override;
  void OnRpcFailed(std::string_view method, absl::StatusCode code) override;
  void OnRpcFinished(std::string_view method, absl::StatusCode code) override;
  void OnFrameSent(uint64_t bytes) override;
  void OnUpdateAnswered(double seconds) override;

  // Serves the text format on http://ADDR/metrics (ADDR = host:port, port 0
  // picks a free one), reading gauges from `engine` at every scrape. With
  // a `token`, a scrape must send it as the password of HTTP Basic
  // authentication (any user name; Prometheus' basic_auth.password_file),
  // else 401. UNAVAILABLE when ADDR cannot be bound. At most once.
  absl::Status Serve(const std::string& address, const Engine& engine,
                     const std::string& token = "");
  // The port bound by Serve (0 before).
  int port() const;
  // Stops the HTTP server and waits for its threads; no scrape reads the
  // engine afterwards. Call before the engine is destroyed. Idempotent.
  void StopServing();

  // What a scrape would answer now (gauges only while serving).
  std::string Text() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gistream::metrics
