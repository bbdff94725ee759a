// gistream-web's Prometheus metrics (`gistream-web --metrics-listen ADDR`,
// GET /metrics on a port of its own, apart from the viewers' port). Counted
// from the HTTP side and the viewer bridges, on any thread; read at each
// scrape. Names: README, "gistream-web". prometheus-cpp stays behind this
// header.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace gistream::web {

class BackendHealth;

class GatewayMetrics {
 public:
  // Why an upgrade to /ws was answered without a viewer.
  enum class Refusal { kOrigin, kViewers, kToken };
  // Why a viewer's gistreamd session was opened again.
  enum class Reopen { kDraining, kUnavailable, kSceneLost };

  GatewayMetrics();
  ~GatewayMetrics();
  GatewayMetrics(const GatewayMetrics&) = delete;
  GatewayMetrics& operator=(const GatewayMetrics&) = delete;

  // An HTTP request answered: `path` is reduced to a bounded set of labels
  // ("/", "/healthz", "/metrics", "/ws", "static", "other").
  void RequestAnswered(std::string_view path, unsigned status);
  void UpgradeRefused(Refusal why);
  void ViewerOpened(bool h264);
  // A frame written to a browser's WebSocket, `bytes` in all.
  void FrameSent(uint64_t bytes);
  // Frames dropped for a browser reading slower than they come.
  void FramesDropped(uint64_t count);
  // Page messages dropped by the --max-messages budget.
  void MessageDropped();
  void SessionReopened(Reopen why);
  // Seconds from the gateway forwarding a page's update to the first frame
  // of gistreamd that shows it (the server's frame plus both gRPC hops; the
  // browser's own hop and decode are the overlay's).
  void UpdateAnswered(double seconds);

  // The text exposition: the counters above, plus gauges read now:
  // live viewers and whether `backend` serves (null: not reported).
  std::string Text(size_t live_viewers, const BackendHealth* backend) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The process's metrics (one gateway per process).
GatewayMetrics& Metrics();

}  // namespace gistream::web
