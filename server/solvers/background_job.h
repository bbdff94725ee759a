// A solver's view-independent work as a job on the CPU pool while frames
// are shaded from its last consistent solution (docs/ARCHITECTURE.md,
// "Updates that run on while frames are shown"). At most one job runs; a
// change while it runs is noted (the job works on a copy of older data)
// and the solver starts another with the newest data once it has taken
// the finished one on the render thread. Used by implicit_visibility's
// relink, antiradiance's link and transport and avg's voxelize and trace.
//
// Each job runs under its own stop token (util/cancellation.h): Cancel(),
// and the destructor, ask it to stop, and its loops end within one step. A
// cancelled job is never taken; the solver that cancels it is on its way
// out (retired by the engine, or destroyed).
#pragma once

#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <utility>

#include "util/cancellation.h"
#include "util/cpu_pool.h"

namespace gistream {

template <typename Job>
class BackgroundJob {
 public:
  BackgroundJob() = default;
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;
  ~BackgroundJob() {  // the job may read the solver's data
    Cancel();
    Wait();
  }

  // Runs `run(*job)` on the CPU pool; its wall time goes to ms(). Only
  // when none runs (check running()).
  void Start(std::shared_ptr<Job> job, std::function<void(Job&)> run) {
    again_ = false;
    job_ = std::move(job);
    stop_ = std::stop_source();
    Job* j = job_.get();
    double* ms = &ms_;
    done_ = CpuPool::Get().Async([j, ms, token = stop_.get_token(), run = std::move(run)] {
      CancellationScope scope(token);
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
  // Asks the running job to stop; it is never taken (TakeIfDone drops it).
  void Cancel() {
    if (job_) stop_.request_stop();
  }
  // A change arrived while the job ran: another is due once it is taken.
  void Again() { again_ = true; }
  bool again() const { return again_; }

  // The finished job (no longer running()), or null while it runs or when
  // none was started.
  std::shared_ptr<Job> TakeIfDone() {
    if (!job_ || done_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
      return nullptr;
    if (stop_.stop_requested()) job_ = nullptr;  // what it left is partial
    return std::exchange(job_, nullptr);
  }
  // Waits for the running job, then takes it.
  std::shared_ptr<Job> TakeWhenDone() {
    Wait();
    if (stop_.stop_requested()) job_ = nullptr;
    return std::exchange(job_, nullptr);
  }
  // The wall time of the last finished job's run.
  double ms() const { return ms_; }

 private:
  void Wait() {
    if (job_ && done_.valid()) done_.wait();
  }

  std::shared_ptr<Job> job_;
  std::stop_source stop_;
  std::shared_future<void> done_;
  bool again_ = false;
  double ms_ = 0.0;
};

}  // namespace gistream
