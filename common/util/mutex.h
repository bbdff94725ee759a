// A std::mutex that clang's thread-safety analysis understands
// (-Wthread-safety): fields can be ABSL_GUARDED_BY it and functions
// ABSL_EXCLUSIVE_LOCKS_REQUIRED it. libstdc++'s std::mutex carries no
// annotations; absl::Mutex does, but Debian's Abseil is not built with
// ThreadSanitizer and synchronizes through futexes TSan cannot see
// (tests/tsan.supp), while std::mutex is pthread's, which TSan intercepts.
#pragma once

#include <mutex>

#include "absl/base/thread_annotations.h"

namespace gistream {

class ABSL_LOCKABLE Mutex {
 public:
  Mutex() = default;
  Mutex(const Mutex&) = delete;
  Mutex& operator=(const Mutex&) = delete;

  void Lock() ABSL_EXCLUSIVE_LOCK_FUNCTION() { mutex_.lock(); }
  void Unlock() ABSL_UNLOCK_FUNCTION() { mutex_.unlock(); }

 private:
  std::mutex mutex_;
};

// Holds `mutex` for its scope.
class ABSL_SCOPED_LOCKABLE MutexLock {
 public:
  explicit MutexLock(Mutex& mutex) ABSL_EXCLUSIVE_LOCK_FUNCTION(mutex) : mutex_(mutex) {
    mutex_.Lock();
  }
  ~MutexLock() ABSL_UNLOCK_FUNCTION() { mutex_.Unlock(); }
  MutexLock(const MutexLock&) = delete;
  MutexLock& operator=(const MutexLock&) = delete;

 private:
  Mutex& mutex_;
};

}  // namespace gistream
