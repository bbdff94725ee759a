// Frames per second over a sliding window, for status reports: the frames
// in (now - 5 s, now] over 5 s, or over the time since the counter started
// when that is shorter. Not thread-safe.
#pragma once

#include <algorithm>
#include <chrono>
#include <deque>

namespace gistream {

class FrameRate {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::seconds kWindow{5};

  explicit FrameRate(Clock::time_point start = Clock::now()) : start_(start) {}

  void Add(Clock::time_point t) {
    times_.push_back(t);
    Prune(t);
  }

  double PerSecond(Clock::time_point now) {
    Prune(now);
    const Clock::duration span = std::min<Clock::duration>(kWindow, now - start_);
    const double seconds = std::chrono::duration<double>(span).count();
    return seconds > 0.0 ? double(times_.size()) / seconds : 0.0;
  }

 private:
  void Prune(Clock::time_point now) {
    while (!times_.empty() && now - times_.front() >= kWindow) times_.pop_front();
  }

  Clock::time_point start_;
  std::deque<Clock::time_point> times_;
};

}  // namespace gistream
