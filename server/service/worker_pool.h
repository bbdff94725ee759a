// A small, bounded pool of threads for blocking Engine calls, so gRPC's
// callback threads never wait on scene loads or renders. Submitting to a
// full queue fails at once with RESOURCE_EXHAUSTED instead of queueing
// without bound; the caller turns that into the RPC's status.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <stop_token>
#include <thread>
#include <vector>

#include "util/status.h"

namespace gistream::service {

class WorkerPool {
 public:
  struct Options {
    /// Threads running jobs.
    size_t threads = 4;
    /// Jobs waiting for a thread; a submit beyond this is refused.
    size_t max_queued = 64;
  };

  explicit WorkerPool(const Options& options);
  // Stop(): runs what is queued, then joins.
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  // Queues `job`. RESOURCE_EXHAUSTED when the queue is full, UNAVAILABLE
  // after Stop(). A job that was accepted always runs.
  absl::Status Submit(std::function<void()> job);

  // Refuses new jobs, runs every job already queued, joins the threads.
  // Idempotent.
  void Stop();

  size_t queued() const;

 private:
  void Run(std::stop_token stop);

  // Configuration
  const size_t max_queued_;

  // Runtime data
  mutable std::mutex mutex_;
  std::condition_variable_any wake_;
  std::deque<std::function<void()>> queue_;
  bool stopping_ = false;
  std::vector<std::jthread> threads_;  // last member: joined first
};

}  // namespace gistream::service
