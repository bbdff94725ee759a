#include "metrics/metrics.h"

#include <exception>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

#include <prometheus/collectable.h>
#include <prometheus/counter.h>
#include <prometheus/exposer.h>
#include <prometheus/family.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>
#include <prometheus/text_serializer.h>

#include "util/process_stats.h"
#include "util/version.h"

namespace gistream::metrics {
namespace {

using prometheus::ClientMetric;
using prometheus::MetricFamily;
using prometheus::MetricType;

// Seconds; frames run from ~1 ms (direct, small) to minutes (pathtrace).
const prometheus::Histogram::BucketBoundaries kFrameBuckets = {
    0.001, 0.002, 0.005, 0.01, 0.02, 0.033, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 30, 60};
// Seconds from an update's arrival to the first frame showing it: a frame
// interval or two at interactive rates, seconds under heavy solvers.
const prometheus::Histogram::BucketBoundaries kLatencyBuckets = {
    0.005, 0.01, 0.02, 0.033, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3, 0.5, 1, 2, 5, 10};
const prometheus::Histogram::BucketBoundaries kStageBuckets = {
    0.0001, 0.0002, 0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 60};

MetricFamily Family(std::string name, std::string help, MetricType type, double value,
                    std::vector<ClientMetric::Label> labels = {}) {
  ClientMetric metric;
  metric.label = std::move(labels);
  if (type == MetricType::Counter) {
    metric.counter.value = value;
  } else {
    metric.gauge.value = value;
  }
  return MetricFamily{std::move(name), std::move(help), type, {std::move(metric)}};
}

std::string CodeName(absl::StatusCode code) { return absl::StatusCodeToString(code); }

// gistream_sessions_by_state{solver, state}: state "streaming" (frames
// rendered as they come), "resting" (a still, finished picture: nothing
// rendered until a change) or "draining" (the server shuts down and has
// told the session to move).
MetricFamily SessionsByState(const EngineStats& stats) {
  std::map<std::pair<std::string, std::string>, double> counts;
  for (const SessionStatus& s : stats.session_status) {
    counts[{s.solver, stats.draining ? "draining" : s.at_rest ? "resting" : "streaming"}] += 1.0;
  }
  MetricFamily family{"gistream_sessions_by_state",
                      "Open sessions by solver and state (streaming, resting, draining)",
                      MetricType::Gauge,
                      {}};
  for (const auto& [key, count] : counts) {
    ClientMetric metric;
    metric.label = {{"solver", key.first}, {"state", key.second}};
    metric.gauge.value = count;
    family.metric.push_back(std::move(metric));
  }
  return family;
}

}  // namespace

struct Metrics::Impl {
  // What the exposer scrapes (it keeps a weak_ptr): Impl's Collect.
  class Collector final : public prometheus::Collectable {
   public:
    explicit Collector(const Impl& impl) : impl_(impl) {}
    std::vector<MetricFamily> Collect() const override { return impl_.Collect(); }

   private:
    const Impl& impl_;
  };

  Impl()
      : registry(std::make_shared<prometheus::Registry>()),
        frames(prometheus::BuildCounter()
                   .Name("gistream_frames_rendered_total")
                   .Help("Frames rendered (sessions and Render calls), by solver")
                   .Register(*registry)),
        dropped(prometheus::BuildCounter()
                    .Name("gistream_frames_dropped_total")
                    .Help("Frames replaced by a newer one before a slow client read them")
                    .Register(*registry)
                    .Add({})),
        rejected(prometheus::BuildCounter()
                     .Name("gistream_updates_rejected_total")
                     .Help("Session updates answered with UpdateRejected, by status code")
                     .Register(*registry)),
        rpc_errors(prometheus::BuildCounter()
                       .Name("gistream_rpc_errors_total")
                       .Help("Calls that ended with a status other than OK, by method and code")
                       .Register(*registry)),
        requests(prometheus::BuildCounter()
                     .Name("gistream_requests_total")
                     .Help("Calls that ended, by method and status code (OK included)")
                     .Register(*registry)),
        bytes_sent(prometheus::BuildCounter()
                       .Name("gistream_frame_bytes_sent_total")
                       .Help("Encoded frame bytes handed to clients (sessions and Render)")
                       .Register(*registry)
                       .Add({})),
        update_latency(prometheus::BuildHistogram()
                           .Name("gistream_update_to_frame_seconds")
                           .Help("From an update's arrival to the first frame that shows it "
                                 "being handed to the client")
                           .Register(*registry)
                           .Add({}, kLatencyBuckets)),
        frame_seconds(prometheus::BuildHistogram()
                          .Name("gistream_frame_seconds")
                          .Help("Frame time on the server (Frame.total_ms), by solver")
                          .Register(*registry)),
        stage_seconds(prometheus::BuildHistogram()
                          .Name("gistream_stage_seconds")
                          .Help("Time of each stage that ran (skipped ones are left out), by "
                                "solver and stage; `where` says whether it is CPU wall time or "
                                "GPU time")
                          .Register(*registry)) {}

  // Registry metrics plus the gauges read now.
  std::vector<MetricFamily> Collect() const {
    std::vector<MetricFamily> out = registry->Collect();
    std::lock_guard lock(engine_mutex);
    if (engine == nullptr) return out;
    const EngineStats stats = engine->stats();
    const ProcessStats process = ReadProcessStats();
    out.push_back(Family("gistream_sessions", "Open sessions", MetricType::Gauge, stats.sessions));
    out.push_back(SessionsByState(stats));
    out.push_back(Family("gistream_scenes", "Loaded scenes", MetricType::Gauge, stats.scenes));
    // Capacity (issue 31): what an autoscaler reads (deploy/k8s/autoscaling.yaml).
    out.push_back(Family("gistream_render_busy_ratio",
                         "Share of the last 5 s the render thread worked (all sessions' GL "
                         "work, readback and encode hand-off): the GPU time in use",
                         MetricType::Gauge, stats.render_busy_ratio));
    out.push_back(Family("gistream_render_busy_limit",
                         "Admission limit on gistream_render_busy_ratio (--max-render-busy; "
                         "0: off)",
                         MetricType::Gauge, stats.max_render_busy));
    out.push_back(Family("gistream_fair_share_deferrals_total",
                         "Times a due frame waited because its tenant had used more render "
                         "time than another tenant with a frame due (the render thread is "
                         "saturated and shared between tenants)",
                         MetricType::Counter, double(stats.fair_share_deferrals)));
    out.push_back(Family("gistream_active_sessions",
                         "Open sessions that cost render time now (not at rest)", MetricType::Gauge,
                         stats.active_sessions));
    out.push_back(Family("gistream_gl_object_bytes",
                         "Bytes held by the engine's GL objects (scenes, solvers, views)",
                         MetricType::Gauge, double(stats.gl_object_bytes)));
    out.push_back(Family("gistream_gpu_memory_total_bytes",
                         "GPU memory as the driver reports it (0: not reported)", MetricType::Gauge,
                         double(stats.gpu_memory_total_bytes)));
    out.push_back(Family("gistream_gpu_memory_available_bytes",
                         "GPU memory available as the driver reports it (0: not reported)",
                         MetricType::Gauge, double(stats.gpu_memory_available_bytes)));
    out.push_back(Family("gistream_memory_budget_used_bytes",
                         "Bytes reserved from the memory budget (scenes, solvers, G-buffers)",
                         MetricType::Gauge, double(stats.memory_used_bytes)));
    out.push_back(Family("gistream_memory_budget_limit_bytes",
                         "The memory budget (--max-memory-bytes)", MetricType::Gauge,
                         double(stats.memory_limit_bytes)));
    out.push_back(Family("process_resident_memory_bytes", "Resident memory of gistreamd",
                         MetricType::Gauge, double(process.rss_bytes)));
    out.push_back(Family("gistream_peak_resident_memory_bytes",
                         "High-water mark of process_resident_memory_bytes", MetricType::Gauge,
                         double(process.peak_rss_bytes)));
    out.push_back(Family("process_cpu_seconds_total", "User and system CPU time of gistreamd",
                         MetricType::Counter, process.cpu_seconds));
    out.push_back(Family("process_start_time_seconds",
                         "Start time of gistreamd, seconds since the Unix epoch", MetricType::Gauge,
                         process.start_time_unix_s));
    out.push_back(Family("gistream_build_info", "Always 1; the version is the label",
                         MetricType::Gauge, 1.0, {{"version", std::string(Version())}}));
    return out;
  }

  std::shared_ptr<prometheus::Registry> registry;
  prometheus::Family<prometheus::Counter>& frames;
  prometheus::Counter& dropped;
  prometheus::Family<prometheus::Counter>& rejected;
  prometheus::Family<prometheus::Counter>& rpc_errors;
  prometheus::Family<prometheus::Counter>& requests;
  prometheus::Counter& bytes_sent;
  prometheus::Histogram& update_latency;
  prometheus::Family<prometheus::Histogram>& frame_seconds;
  prometheus::Family<prometheus::Histogram>& stage_seconds;

  const std::shared_ptr<Collector> collector = std::make_shared<Collector>(*this);
  mutable std::mutex engine_mutex;
  const Engine* engine = nullptr;  // while serving
  // Declared last: destroyed (HTTP threads joined) before the rest.
  std::unique_ptr<prometheus::Exposer> exposer;
};

Metrics::Metrics() : impl_(std::make_unique<Impl>()) {}

Metrics::~Metrics() { StopServing(); }

void Metrics::OnFrameRendered(const EncodedFrame& frame) {
  impl_->frames.Add({{"solver", frame.solver}}).Increment();
  impl_->frame_seconds.Add({{"solver", frame.solver}}, kFrameBuckets).Observe(frame.total_ms / 1e3);
  for (const StageTiming& stage : frame.timings) {
    if (stage.skipped) continue;
    impl_->stage_seconds
        .Add({{"solver", frame.solver},
              {"stage", stage.name},
              {"where", stage.cpu_stage ? "cpu" : "gpu"}},
             kStageBuckets)
        .Observe((stage.cpu_stage ? stage.cpu_ms : stage.gpu_ms) / 1e3);
  }
}

void Metrics::OnFramesDropped(uint64_t count) { impl_->dropped.Increment(double(count)); }

void Metrics::OnUpdateRejected(absl::StatusCode code) {
  impl_->rejected.Add({{"code", CodeName(code)}}).Increment();
}

void Metrics::OnRpcFinished(std::string_view method, absl::StatusCode code) {
  impl_->requests.Add({{"method", std::string(method)}, {"code", CodeName(code)}}).Increment();
}

void Metrics::OnFrameSent(uint64_t bytes) { impl_->bytes_sent.Increment(double(bytes)); }

void Metrics::OnUpdateAnswered(double seconds) { impl_->update_latency.Observe(seconds); }

void Metrics::OnRpcFailed(std::string_view method, absl::StatusCode code) {
  impl_->rpc_errors.Add({{"method", std::string(method)}, {"code", CodeName(code)}}).Increment();
}

absl::Status Metrics::Serve(const std::string& address, const Engine& engine,
                            const std::string& token) {
  if (impl_->exposer != nullptr) return absl::FailedPreconditionError("metrics: already serving");
  {
    std::lock_guard lock(impl_->engine_mutex);
    impl_->engine = &engine;
  }
  try {
    impl_->exposer = std::make_unique<prometheus::Exposer>(address, /*num_threads=*/2);
  } catch (const std::exception& e) {
    std::lock_guard lock(impl_->engine_mutex);
    impl_->engine = nullptr;
    return absl::UnavailableError(
        absl::StrCat("--metrics-listen: cannot listen on ", address, ": ", e.what()));
  }
  impl_->exposer->RegisterCollectable(impl_->collector);
  if (!token.empty()) {
    impl_->exposer->RegisterAuth(
        [token](const std::string& /*user*/, const std::string& password) {
          // In time independent of where the strings differ.
          unsigned diff = unsigned(password.size() ^ token.size());
          for (size_t i = 0; i < token.size(); ++i) {
            diff |= unsigned(uint8_t(token[i]) ^ uint8_t(i < password.size() ? password[i] : 0));
          }
          return diff == 0;
        },
        "gistreamd metrics");
  }
  return absl::OkStatus();
}

int Metrics::port() const {
  if (impl_->exposer == nullptr) return 0;
  const std::vector<int> ports = impl_->exposer->GetListeningPorts();
  return ports.empty() ? 0 : ports.front();
}

void Metrics::StopServing() {
  impl_->exposer.reset();  // joins the HTTP threads: no scrape runs after this
  std::lock_guard lock(impl_->engine_mutex);
  impl_->engine = nullptr;
}

std::string Metrics::Text() const {
  return prometheus::TextSerializer().Serialize(impl_->Collect());
}

}  // namespace gistream::metrics
