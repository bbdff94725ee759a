// The CPU time of a background job's stages (solvers/background_job.h):
// measured on the pool while the job runs, recorded into the stage table
// of the frame that takes the job (StageTimer::Record), so every solver's
// stage table shows its background stages the same way.
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <utility>

#include "gl/stage_timer.h"

namespace gistream {

class JobStageTimes {
 public:
  // Runs fn() and adds its wall time to `stage`.
  template <typename Fn>
  void Time(const std::string& stage, Fn&& fn) {
    const auto start = Clock::now();
    std::forward<Fn>(fn)();
    Add(stage, Since(start));
  }
  // For work that reports its stages through begin/end callbacks (one
  // stage at a time): Begin starts the clock, End adds to `stage`.
  void Begin() { begun_ = Clock::now(); }
  void End(const std::string& stage) { Add(stage, Since(begun_)); }

  void Add(const std::string& stage, double ms) { ms_[stage] += ms; }
  bool ran(const std::string& stage) const { return ms_.contains(stage); }
  // Reports every timed stage in `timer`'s frame.
  void RecordInto(gl::StageTimer& timer) const {
    for (const auto& [stage, ms] : ms_) timer.Record(stage, ms);
  }

 private:
  using Clock = std::chrono::steady_clock;
  static double Since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  }

  std::map<std::string, double> ms_;
  Clock::time_point begun_;
};

}  // namespace gistream
