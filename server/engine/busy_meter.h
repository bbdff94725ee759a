// The share of wall time a thread spent working over a recent window: the
// render thread's load, which admission and the capacity metrics use
// (issue 31: capacity from GPU time). The render thread submits and waits
// for every GL command of every session, so its busy share is the GPU
// time the server sells, whatever the device.
#pragma once

#include <chrono>
#include <deque>
#include <mutex>

namespace gistream {

class BusyMeter {
 public:
  using Clock = std::chrono::steady_clock;

  explicit BusyMeter(Clock::duration window = std::chrono::seconds(5)) : window_(window) {}

  // One busy interval of the measured thread (it ended at `end`).
  void AddBusy(Clock::time_point start, Clock::time_point end);
  // Busy share of [now - window, now], in [0, 1]; before a whole window has
  // passed since the first interval, of the time since then.
  double Ratio(Clock::time_point now = Clock::now()) const;

 private:
  const Clock::duration window_;
  mutable std::mutex mutex_;
  mutable std::deque<std::pair<Clock::time_point, Clock::time_point>> busy_;
  Clock::time_point first_{};
  bool any_ = false;
};

}  // namespace gistream
