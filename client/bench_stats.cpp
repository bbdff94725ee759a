#include "bench_stats.h"

#include <algorithm>
#include <numeric>

namespace gistream::client {
namespace {

double Ms(BenchClock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

}  // namespace

void LatencyTracker::OnSend(uint64_t seq, BenchClock::time_point sent, bool measured) {
  pending_[seq] = Pending{sent, measured};
}

int LatencyTracker::OnFrame(uint64_t last_update_seq, BenchClock::time_point arrival) {
  int answered = 0;
  // Every pending update with seq <= last_update_seq is in this frame.
  auto end = pending_.upper_bound(last_update_seq);
  for (auto it = pending_.begin(); it != end; ++it) {
    if (it->second.measured) latencies_ms_.push_back(std::max(0.0, Ms(arrival - it->second.sent)));
    ++answered;
  }
  pending_.erase(pending_.begin(), end);
  return answered;
}

void LatencyTracker::OnRejected(uint64_t seq) {
  auto it = pending_.find(seq);
  if (it == pending_.end()) return;
  if (it->second.measured) ++rejected_;
  pending_.erase(it);
}

size_t LatencyTracker::unanswered() const {
  return size_t(std::count_if(pending_.begin(), pending_.end(),
                              [](const auto& p) { return p.second.measured; }));
}

std::optional<double> LatencyTracker::OldestPendingAgeMs(BenchClock::time_point now) const {
  for (const auto& [seq, p] : pending_) {
    if (p.measured) return std::max(0.0, Ms(now - p.sent));
  }
  return std::nullopt;
}

bool FrameIntervals::Add(BenchClock::time_point arrival) {
  if (arrival < start_ || arrival >= end_) return false;
  arrivals_.push_back(arrival);
  return true;
}

void FrameIntervals::Finish(SessionMeasurement& out) const {
  out.frames = int(arrivals_.size());
  out.intervals_ms.clear();
  for (size_t i = 1; i < arrivals_.size(); ++i) {
    out.intervals_ms.push_back(Ms(arrivals_[i] - arrivals_[i - 1]));
  }
  double gap = arrivals_.empty() ? Ms(end_ - start_) : 0.0;
  if (!arrivals_.empty()) {
    gap = std::max(Ms(arrivals_.front() - start_), Ms(end_ - arrivals_.back()));
  }
  for (double interval : out.intervals_ms) gap = std::max(gap, interval);
  out.max_gap_ms = gap;
}

double JainFairness(const std::vector<double>& values) {
  if (values.empty()) return 1.0;
  double sum = 0.0, sum_sq = 0.0;
  for (double v : values) {
    sum += v;
    sum_sq += v * v;
  }
  if (sum_sq <= 0.0) return 1.0;
  return sum * sum / (double(values.size()) * sum_sq);
}

Quantiles Summarize(const std::vector<double>& values) {
  Quantiles q;
  q.p50 = Percentile(values, 50);
  q.p95 = Percentile(values, 95);
  q.p99 = Percentile(values, 99);
  q.max = Percentile(values, 100);
  return q;
}

StepResult AggregateStep(std::vector<SessionMeasurement> sessions, StatsSummary stages,
                         double window_s) {
  StepResult step;
  step.sessions = int(sessions.size());
  step.window_s = window_s;
  std::vector<double> intervals, fps, settle;
  double max_gap = 0.0;
  uint64_t bytes = 0;
  for (const SessionMeasurement& s : sessions) {
    step.all_latencies_ms.insert(step.all_latencies_ms.end(), s.latencies_ms.begin(),
                                 s.latencies_ms.end());
    intervals.insert(intervals.end(), s.intervals_ms.begin(), s.intervals_ms.end());
    max_gap = std::max(max_gap, s.max_gap_ms);
    fps.push_back(s.fps());
    step.frames += uint64_t(s.frames);
    step.dropped += s.dropped_frames;
    step.updates_sent += s.updates_sent;
    step.updates_answered += s.latencies_ms.size();
    step.updates_rejected += s.updates_rejected;
    step.updates_unanswered += s.updates_unanswered;
    bytes += s.bytes;
    if (s.settle_ms) {
      settle.push_back(*s.settle_ms);
    } else {
      ++step.unsettled;
    }
    if (!s.error.empty() && step.failed_sessions++ == 0) step.first_error = s.error;
  }
  std::sort(step.all_latencies_ms.begin(), step.all_latencies_ms.end());
  step.latency_ms = Summarize(step.all_latencies_ms);
  step.interval_ms = Summarize(intervals);
  step.settle_ms = Summarize(settle);
  if (!sessions.empty())
    step.interval_ms.max = std::max(step.interval_ms.max.value_or(0.0), max_gap);
  if (!fps.empty()) {
    step.fps_total = std::accumulate(fps.begin(), fps.end(), 0.0);
    step.fps_mean = step.fps_total / double(fps.size());
    step.fps_min = *std::min_element(fps.begin(), fps.end());
  }
  step.jain = JainFairness(fps);
  step.bytes_per_s = window_s > 0.0 ? double(bytes) / window_s : 0.0;
  step.stages = std::move(stages);
  step.per_session = std::move(sessions);
  return step;
}

}  // namespace gistream::client
