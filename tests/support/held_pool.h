// Holds every worker of the CPU pool (util/cpu_pool.h) until Release() or
// destruction, so a background job started meanwhile cannot run: a test
// can show that a caller returns without waiting for one. With a pool of
// one thread Async runs inline (a job runs before Start returns); nothing
// is held then.
#pragma once

#include <future>
#include <latch>
#include <vector>

#include "util/cpu_pool.h"

namespace gistream::testing {

class HeldPool {
 public:
  HeldPool() {
    const unsigned workers = CpuPool::Get().threads() - 1;
    std::latch started(workers);
    const std::shared_future<void> gate = release_.get_future().share();
    for (unsigned i = 0; i < workers; ++i) {
      held_.push_back(CpuPool::Get().Async([&started, gate] {
        started.count_down();
        gate.wait();
      }));
    }
    started.wait();
  }
  HeldPool(const HeldPool&) = delete;
  HeldPool& operator=(const HeldPool&) = delete;
  ~HeldPool() { Release(); }

  void Release() {
    if (released_) return;
    released_ = true;
    release_.set_value();
    for (const std::shared_future<void>& f : held_) f.wait();
  }
  // Whether a job started now would wait (false with a one-thread pool).
  static bool Holds() { return CpuPool::Get().threads() > 1; }

 private:
  std::promise<void> release_;
  std::vector<std::shared_future<void>> held_;
  bool released_ = false;
};

}  // namespace gistream::testing
