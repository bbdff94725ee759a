#include "service/worker_pool.h"

#include <algorithm>
#include <utility>

#include "util/log.h"

namespace gistream::service {

WorkerPool::WorkerPool(const Options& options)
    : max_queued_(std::max<size_t>(options.max_queued, 1)) {
  const size_t n = std::max<size_t>(options.threads, 1);
  threads_.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    threads_.emplace_back([this](std::stop_token stop) { Run(stop); });
  }
}

WorkerPool::~WorkerPool() { Stop(); }

absl::Status WorkerPool::Submit(std::function<void()> job) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return absl::UnavailableError("server is shutting down");
    if (queue_.size() >= max_queued_) {
      return absl::ResourceExhaustedError(
          absl::StrCat("server busy: ", queue_.size(), " requests already queued"));
    }
    queue_.push_back(std::move(job));
  }
  wake_.notify_one();
  return absl::OkStatus();
}

void WorkerPool::Stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && threads_.empty()) return;
    stopping_ = true;
  }
  for (auto& t : threads_) t.request_stop();
  for (auto& t : threads_) {
    if (t.joinable()) t.join();
  }
  std::lock_guard lock(mutex_);
  threads_.clear();
}

size_t WorkerPool::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

void WorkerPool::Run(std::stop_token stop) {
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock lock(mutex_);
      // Returns false only when stop was requested and nothing is queued:
      // queued jobs still run after a stop request (their RPCs must finish).
      if (!wake_.wait(lock, stop, [this] { return !queue_.empty(); })) return;
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    try {
      job();
    } catch (const std::exception& e) {
      // A job must finish its RPC itself; an escaping exception is our bug.
      Log(LogLevel::kError, absl::StrCat("worker job threw: ", e.what()));
    }
  }
}

}  // namespace gistream::service
