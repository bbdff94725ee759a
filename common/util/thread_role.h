// A thread's role as a capability for clang's thread-safety analysis
// (-Wthread-safety): state that only one thread may touch (the render
// thread's GL objects and views) is ABSL_GUARDED_BY(role), the functions
// that run there are ABSL_EXCLUSIVE_LOCKS_REQUIRED(role), and each entry
// point on that thread (a posted job, the scheduler's tick) starts with
// role.Assert(). Nothing is locked: the analysis checks at compile time that
// no other thread's code path reaches the state without passing an
// Assert, and Assert checks at run time that the caller is on the thread
// (an atomic load; a wrong thread is a bug, reported and aborted on). Chromium's ThreadChecker and
// Falcor's render-thread asserts follow the same idea.
#pragma once

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "absl/base/thread_annotations.h"

namespace gistream {

class ABSL_LOCKABLE ThreadRole {
 public:
  explicit ThreadRole(const char* name) : name_(name) {}

  // Called on the thread that plays the role from now on (its entry
  // point, which then holds the role). Until then Assert checks nothing at
  // run time.
  void Bind() ABSL_ASSERT_EXCLUSIVE_LOCK() {
    thread_.store(std::this_thread::get_id(), std::memory_order_relaxed);
  }

  // The caller runs on the role's thread; aborts the process, naming the
  // role, when it does not.
  void Assert() const ABSL_ASSERT_EXCLUSIVE_LOCK() {
    const std::thread::id bound = thread_.load(std::memory_order_relaxed);
    if (bound != std::thread::id() && bound != std::this_thread::get_id()) {
      std::fprintf(stderr, "FATAL: %s state touched off its thread\n", name_);
      std::abort();
    }
  }

 private:
  const char* name_;  // for the message
  std::atomic<std::thread::id> thread_{};
};

}  // namespace gistream
