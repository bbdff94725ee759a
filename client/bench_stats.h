// What `gistream bench` measures, without the network: update-to-frame
// latency matching, frame intervals, per-session and per-step summaries
// (percentiles, Jain's fairness index). Times are passed in, so tests drive
// these with synthetic clocks.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gistream/v1/gistream.pb.h"
#include "stats_table.h"

namespace gistream::client {

using BenchClock = std::chrono::steady_clock;

// Update-to-frame latency: the time from sending update `seq` to receiving
// the first frame whose last applied sequence number is >= seq. Frames
// echo the largest seq applied so far, so one frame can answer several
// updates at once. Thread-compatible (one owner).
class LatencyTracker {
 public:
  // `measured`: whether this update's latency counts (sent inside the
  // measurement window); unmeasured ones are still matched, so they never
  // delay the matching of later ones.
  void OnSend(uint64_t seq, BenchClock::time_point sent, bool measured = true);
  // Returns how many pending updates this frame answered.
  int OnFrame(uint64_t last_update_seq, BenchClock::time_point arrival);
  // A rejected update is answered by the rejection, not by a frame: it
  // leaves the pending set and counts as rejected.
  void OnRejected(uint64_t seq);

  const std::vector<double>& latencies_ms() const { return latencies_ms_; }
  // Measured updates still waiting for a frame.
  size_t unanswered() const;
  uint64_t rejected() const { return rejected_; }
  // The oldest measured update still unanswered: its age at `now` is a
  // lower bound of its latency (shows a stall that never ended).
  std::optional<double> OldestPendingAgeMs(BenchClock::time_point now) const;

 private:
  struct Pending {
    BenchClock::time_point sent;
    bool measured;
  };
  std::map<uint64_t, Pending> pending_;  // by seq
  std::vector<double> latencies_ms_;
  uint64_t rejected_ = 0;
};

// Everything one session saw inside the measurement window.
struct SessionMeasurement {
  std::string server;
  int frames = 0;
  double window_s = 0.0;
  std::vector<double> intervals_ms;  // between consecutive frames in the window
  // The longest time without a frame, including the open gap at either
  // end of the window (so a stream that stopped entirely still shows).
  double max_gap_ms = 0.0;
  uint64_t dropped_frames = 0;
  uint64_t bytes = 0;  // encoded image bytes
  uint64_t updates_sent = 0;
  uint64_t updates_rejected = 0;
  uint64_t updates_unanswered = 0;
  std::vector<double> latencies_ms;
  // From the end of the updates to the first frame that includes the last
  // one and whose GI update is complete (stat update_complete): the time
  // to converge once motion stops. nullopt when that frame never came.
  std::optional<double> settle_ms;
  std::string error;  // the session's failure, if it failed
  // Moves to another server (its server drained or died): how many, and
  // for each completed one the time without frames (the last frame of the
  // old server to the first of the new) and from the failure to the first
  // frame showing every acknowledged update.
  int moves = 0;
  std::vector<double> move_gap_ms, move_to_acked_ms;

  double fps() const { return window_s > 0.0 ? frames / window_s : 0.0; }
};

// Frames of one session against the window [start, end).
class FrameIntervals {
 public:
  FrameIntervals(BenchClock::time_point start, BenchClock::time_point end)
      : start_(start), end_(end) {}
  // Returns whether the arrival lies inside the window.
  bool Add(BenchClock::time_point arrival);
  // Fills frames, intervals_ms and max_gap_ms.
  void Finish(SessionMeasurement& out) const;

 private:
  BenchClock::time_point start_, end_;
  std::vector<BenchClock::time_point> arrivals_;
};

// (Σx)² / (n Σx²): 1 when every session gets the same, 1/n when one gets
// everything. 1 for no sessions or all zero.
double JainFairness(const std::vector<double>& values);

struct Quantiles {
  std::optional<double> p50, p95, p99, max;
};
Quantiles Summarize(const std::vector<double>& values);

// Server-side figures sampled from GetServerStatus during a step.
struct ServerSample {
  std::string server;
  uint64_t max_rss_bytes = 0;
  double cpu_percent = 0.0;  // CPU seconds / wall seconds x 100 over the window
  bool available = false;
};

// One concurrency step, aggregated over its sessions.
struct StepResult {
  int sessions = 0;
  double window_s = 0.0;
  std::vector<SessionMeasurement> per_session;
  Quantiles latency_ms;   // pooled over sessions
  Quantiles interval_ms;  // pooled; max is the longest gap (window ends included)
  double fps_mean = 0.0;  // per session
  double fps_min = 0.0;
  double fps_total = 0.0;
  double jain = 1.0;
  uint64_t frames = 0;
  uint64_t dropped = 0;
  uint64_t updates_sent = 0;
  uint64_t updates_answered = 0;
  uint64_t updates_rejected = 0;
  uint64_t updates_unanswered = 0;
  Quantiles settle_ms;  // over the sessions that settled
  int unsettled = 0;    // sessions that did not settle before the drain ended
  double bytes_per_s = 0.0;
  int failed_sessions = 0;
  std::string first_error;  // the first failed session's
  StatsSummary stages;      // the server's per-stage timings, over all frames
  std::vector<ServerSample> servers;
  // The interferer, when one ran: renders finished and their median time.
  int interferer_renders = 0;
  std::optional<double> interferer_median_ms;
  std::string interferer_error;
  // Every latency, for the CDF plot (sorted).
  std::vector<double> all_latencies_ms;
};

// Aggregates the per-session measurements (and `stages`, collected over
// every frame of the step) into a StepResult.
StepResult AggregateStep(std::vector<SessionMeasurement> sessions, StatsSummary stages,
                         double window_s);

}  // namespace gistream::client
