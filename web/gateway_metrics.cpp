#include "gateway_metrics.h"

#include <utility>
#include <vector>

#include <prometheus/counter.h>
#include <prometheus/family.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>
#include <prometheus/text_serializer.h>

#include "backend_health.h"
#include "util/version.h"

namespace gistream::web {
namespace {

using prometheus::ClientMetric;
using prometheus::MetricFamily;
using prometheus::MetricType;

// Seconds from an update forwarded to the first frame showing it: a frame
// interval or two at interactive rates, seconds under heavy solvers (the
// same buckets as gistreamd's gistream_update_to_frame_seconds).
const prometheus::Histogram::BucketBoundaries kLatencyBuckets = {
    0.005, 0.01, 0.02, 0.033, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3, 0.5, 1, 2, 5, 10};

MetricFamily Gauge(std::string name, std::string help, double value,
                   std::vector<ClientMetric::Label> labels = {}) {
  ClientMetric metric;
  metric.label = std::move(labels);
  metric.gauge.value = value;
  return MetricFamily{std::move(name), std::move(help), MetricType::Gauge, {std::move(metric)}};
}

std::string_view PathLabel(std::string_view path) {
  for (std::string_view known : {"/", "/healthz", "/metrics", "/ws"}) {
    if (path == known) return known;
  }
  // The embedded page's files; anything else is a 404 under "other".
  return path.find('.') != std::string_view::npos && path.find('/', 1) == std::string_view::npos
             ? "static"
             : "other";
}

}  // namespace

struct GatewayMetrics::Impl {
  prometheus::Registry registry;
  prometheus::Family<prometheus::Counter>& requests =
      prometheus::BuildCounter()
          .Name("gistream_web_http_requests_total")
          .Help("HTTP requests answered, by path and status code")
          .Register(registry);
  prometheus::Family<prometheus::Counter>& refused =
      prometheus::BuildCounter()
          .Name("gistream_web_upgrades_refused_total")
          .Help(
              "WebSocket upgrades refused: reason origin (not in --allow-origin), viewers "
              "(--max-viewers reached) or token (no valid --viewer-tokens token)")
          .Register(registry);
  prometheus::Counter& refused_origin = refused.Add({{"reason", "origin"}});
  prometheus::Counter& refused_viewers = refused.Add({{"reason", "viewers"}});
  prometheus::Counter& refused_token = refused.Add({{"reason", "token"}});
  prometheus::Family<prometheus::Counter>& opened =
      prometheus::BuildCounter()
          .Name("gistream_web_viewers_opened_total")
          .Help("Viewers (WebSocket sessions) opened, by frame format")
          .Register(registry);
  prometheus::Counter& opened_jpeg = opened.Add({{"format", "jpeg"}});
  prometheus::Counter& opened_h264 = opened.Add({{"format", "h264"}});
  prometheus::Counter& frames_sent = prometheus::BuildCounter()
                                         .Name("gistream_web_frames_sent_total")
                                         .Help("Frames written to browsers")
                                         .Register(registry)
                                         .Add({});
  prometheus::Counter& bytes_sent = prometheus::BuildCounter()
                                        .Name("gistream_web_frame_bytes_sent_total")
                                        .Help("Bytes of frame messages written to browsers")
                                        .Register(registry)
                                        .Add({});
  prometheus::Counter& frames_dropped =
      prometheus::BuildCounter()
          .Name("gistream_web_frames_dropped_total")
          .Help("Frames dropped for browsers reading slower than frames come")
          .Register(registry)
          .Add({});
  prometheus::Counter& messages_dropped =
      prometheus::BuildCounter()
          .Name("gistream_web_messages_dropped_total")
          .Help("Page messages dropped by the --max-messages budget")
          .Register(registry)
          .Add({});
  prometheus::Family<prometheus::Counter>& reopened =
      prometheus::BuildCounter()
          .Name("gistream_web_sessions_reopened_total")
          .Help(
              "Viewers' gistreamd sessions opened again: reason draining (the server said "
              "so), unavailable (the call broke) or scene_lost (the backend restarted)")
          .Register(registry);
  prometheus::Counter& reopened_draining = reopened.Add({{"reason", "draining"}});
  prometheus::Counter& reopened_unavailable = reopened.Add({{"reason", "unavailable"}});
  prometheus::Counter& reopened_scene_lost = reopened.Add({{"reason", "scene_lost"}});
  prometheus::Histogram& update_latency =
      prometheus::BuildHistogram()
          .Name("gistream_web_update_to_frame_seconds")
          .Help("From a page's update forwarded to gistreamd to the first frame showing it")
          .Register(registry)
          .Add({}, kLatencyBuckets);
};

GatewayMetrics::GatewayMetrics() : impl_(std::make_unique<Impl>()) {}
GatewayMetrics::~GatewayMetrics() = default;

void GatewayMetrics::RequestAnswered(std::string_view path, unsigned status) {
  // Add is idempotent for equal labels (a lookup under the family's lock).
  impl_->requests.Add({{"path", std::string(PathLabel(path))}, {"code", std::to_string(status)}})
      .Increment();
}

void GatewayMetrics::UpgradeRefused(Refusal why) {
  (why == Refusal::kOrigin    ? impl_->refused_origin
   : why == Refusal::kViewers ? impl_->refused_viewers
                              : impl_->refused_token)
      .Increment();
}

void GatewayMetrics::ViewerOpened(bool h264) {
  (h264 ? impl_->opened_h264 : impl_->opened_jpeg).Increment();
}

void GatewayMetrics::FrameSent(uint64_t bytes) {
  impl_->frames_sent.Increment();
  impl_->bytes_sent.Increment(double(bytes));
}

void GatewayMetrics::FramesDropped(uint64_t count) {
  impl_->frames_dropped.Increment(double(count));
}

void GatewayMetrics::MessageDropped() { impl_->messages_dropped.Increment(); }

void GatewayMetrics::SessionReopened(Reopen why) {
  (why == Reopen::kDraining      ? impl_->reopened_draining
   : why == Reopen::kUnavailable ? impl_->reopened_unavailable
                                 : impl_->reopened_scene_lost)
      .Increment();
}

void GatewayMetrics::UpdateAnswered(double seconds) { impl_->update_latency.Observe(seconds); }

std::string GatewayMetrics::Text(size_t live_viewers, const BackendHealth* backend) const {
  std::vector<MetricFamily> families = impl_->registry.Collect();
  families.push_back(Gauge("gistream_web_viewers", "Viewers connected now", double(live_viewers)));
  if (backend != nullptr) {
    families.push_back(Gauge("gistream_web_backend_serving",
                             "1 while the gistreamd behind the gateway answers SERVING, else 0",
                             backend->state().serving ? 1.0 : 0.0));
  }
  families.push_back(Gauge("gistream_web_build_info", "The gateway's version", 1.0,
                           {{"version", std::string(Version())}}));
  return prometheus::TextSerializer().Serialize(families);
}

GatewayMetrics& Metrics() {
  static GatewayMetrics* metrics = new GatewayMetrics();  // never destroyed: threads outlive main
  return *metrics;
}

}  // namespace gistream::web
