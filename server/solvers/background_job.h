// A solver's view-independent work as a job on the CPU pool while frames
// are shaded from its last consistent solution (docs/ARCHITECTURE.md,
// "Updates that run on while frames are shown"). At most one job runs; a
// change while it runs is noted (the job works on a copy of older data)
// and the solver starts another with the newest data once it has taken
// the finished one on the render thread. Used by implicit_visibility's
// relink, antiradiance's link and transport and avg's voxelize and trace.
#pragma once

#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <utility>

#include "util/cpu_pool.h"

namespace gistream {

template <typename Job>
class BackgroundJob {
 public:
  BackgroundJob() = default;
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;
  ~BackgroundJob() { Wait(); }  // the job may read the solver's data

  // Runs `run(*job)` on the CPU pool; its wall time goes to ms(). Only
  // when none runs (check running()).
  void Start(std::shared_ptr<Job> job, std::function<void(Job&)> run) {
    again_ = false;
    job_ = std::move(job);
    Job* j = job_.get();
    double* ms = &ms_;
    done_ = CpuPool::Get().Async([j, ms, run = std::move(run)] {
      const auto start = std::chrono::steady_clock::now();
      run(*j);
      *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
    });
  }
  bool running() const { return job_ != nullptr; }
  // Whether the job's run has not returned yet (running() also holds a
  // finished job until it is taken).
  bool executing() const {
    return job_ && done_.valid() &&
           done_.wait_for(std::chrono::seconds(0)) != std::future_status::ready;
  }
  // A change arrived while the job ran: another is due once it is taken.
  void Again() { again_ = true; }
  bool again() const { return again_; }

  // The finished job (no longer running()), or null while it runs or when
  // none was started.
  std::shared_ptr<Job> TakeIfDone() {
    if (!job_ || done_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
      return nullptr;
    return std::exchange(job_, nullptr);
  }
  // Waits for the running job, then takes it.
  std::shared_ptr<Job> TakeWhenDone() {
    Wait();
    return std::exchange(job_, nullptr);
  }
  // The wall time of the last finished job's run.
  double ms() const { return ms_; }

 private:
  void Wait() {
    if (job_ && done_.valid()) done_.wait();
  }

  std::shared_ptr<Job> job_;
  std::shared_future<void> done_;
  bool again_ = false;
  double ms_ = 0.0;
};

}  // namespace gistream
