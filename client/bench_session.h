// One session of a `gistream bench` step: a reader thread that times every
// frame and matches it to the updates it answers, and (open loop) a sender
// thread at the update rate; closed loop sends one tick's updates per
// received frame. The coordinator opens it, sets the measurement window
// once every session has its first frame, stops the updates at the window's
// end, drains, closes, and collects a SessionMeasurement.
#pragma once

#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bench_stats.h"
#include "bench_workload.h"
#include "resumable_session.h"
#include "stats_table.h"

namespace gistream::client {

// Frames of every session of a step feed one stage collector.
struct SharedStages {
  std::mutex mutex;
  StatsCollector collector;
};

class BenchSession {
 public:
  BenchSession(std::string server, const Workload& workload, double update_hz, SharedStages& stages)
      : server_(std::move(server)), workload_(workload), update_hz_(update_hz), stages_(stages) {}
  ~BenchSession();  // cancels and joins whatever still runs
  BenchSession(const BenchSession&) = delete;
  BenchSession& operator=(const BenchSession&) = delete;

  // Opens the call (waits for `opened`) and starts the threads. A failure
  // is kept as the session's error. When its server drains or dies the
  // session moves (ResumableSession, through `resume`'s address) and the
  // move's times are in the result.
  absl::Status Open(v1::Gistream::Stub& stub, const v1::SessionConfig& config,
                    ResumeOptions resume);

  bool failed() const;
  bool has_first_frame() const { return first_frame_.load(); }
  // Frames before `start` are warm-up; updates sent inside [start, end)
  // are measured.
  void SetWindow(BenchClock::time_point start, BenchClock::time_point end);
  // No more updates (the window has ended).
  void StopUpdates();
  // Measured updates not yet answered by a frame.
  size_t Unanswered() const;
  // Whether a frame after StopUpdates included the last update and had its
  // GI update complete (see SessionMeasurement::settle_ms).
  bool Settled() const;
  // Half-closes, waits for the server to end the call, joins the threads.
  void Close();
  // After Close.
  SessionMeasurement Result() const;

  // Keeps the images of the frames that show the last update (from the
  // first such frame after StopUpdates to the settled one), for the time
  // to converge against a reference (bench --reference-spp).
  void KeepSettleFrames() { keep_settle_frames_ = true; }
  struct SettleFrame {
    double ms = 0.0;  // after StopUpdates
    std::string image;
  };
  // After Close: those frames, and every update sent, in order (the state
  // they show, from the scene as loaded).
  std::vector<SettleFrame> SettleFrames() const;
  std::vector<v1::Update> LastState() const;

  // With KeepSettleFrames, every frame from the window's start too (issue
  // 27: the error of each frame shown, during the motion and after it).
  struct TracedFrame {
    double t_ms = 0.0;  // since the window's start
    uint64_t frame_number = 0;
    uint64_t seq = 0;     // last_update_seq: the state it shows
    bool settle = false;  // after StopUpdates (else during the motion)
    std::string image;    // the picture shown (an unchanged frame's is the last)
    double update_complete = 1.0, at_rest = 0.0, frames_since_scene_change = 0.0;
    double refine_samples = 1.0;  // the still view's samples per pixel in it
  };
  std::vector<TracedFrame> TracedFrames() const;
  // The state a frame showing sequence number `seq` shows: every update
  // sent up to it, in order (each sets what it names, so replaying them on
  // the scene as loaded gives that state, whatever the workload); empty
  // for 0 (the scene as loaded). With KeepSettleFrames.
  std::vector<v1::Update> StateOfSeq(uint64_t seq) const;

  // Live figures for the progress line: frames inside the window so far,
  // and a copy of the latencies measured so far.
  int LiveFrames() const;
  void AppendLatencies(std::vector<double>& out) const;

 private:
  void ReadLoop();
  void SendLoop();
  void SendTick();

  const std::string server_;
  const Workload& workload_;
  const double update_hz_;
  SharedStages& stages_;

  std::unique_ptr<ResumableSession> stream_;
  std::thread reader_, sender_;
  std::atomic<bool> first_frame_{false};
  std::atomic<bool> stop_updates_{false};

  mutable std::mutex mutex_;
  std::condition_variable stop_cv_;  // wakes the sender
  bool window_set_ = false;
  BenchClock::time_point window_start_{}, window_end_{};
  std::unique_ptr<FrameIntervals> intervals_;
  LatencyTracker tracker_;
  uint64_t tick_ = 0;
  uint64_t next_seq_ = 1;
  uint64_t updates_sent_ = 0;  // measured ones
  uint64_t last_seq_sent_ = 0;
  BenchClock::time_point stopped_at_{};
  std::optional<double> settle_ms_;
  std::atomic<bool> keep_settle_frames_{false};
  std::vector<SettleFrame> settle_frames_;
  std::vector<TracedFrame> traced_frames_;
  std::vector<v1::Update> sent_;  // with KeepSettleFrames: every update sent, seq set
  std::string last_image_;        // the last frame's that had one
  uint64_t dropped_ = 0;
  uint64_t bytes_ = 0;
  int live_frames_ = 0;
  std::string error_;
};

}  // namespace gistream::client
