// Ctrl-C (SIGINT) and SIGTERM for a client that holds a streaming call:
// the signal is taken on a watcher thread and handed to the command, which
// half-closes its session and prints its table instead of dying mid-frame.
#pragma once

#include <atomic>
#include <functional>
#include <thread>

namespace gistream::client {

// Create one first thing in main(), before gRPC starts any thread, so that
// every thread inherits the blocked signal mask and only the watcher sees
// the signals. While no handler is installed, an interrupt exits at once
// with status 130, as an unhandled SIGINT would.
class InterruptWatcher {
 public:
  InterruptWatcher();
  ~InterruptWatcher();
  InterruptWatcher(const InterruptWatcher&) = delete;
  InterruptWatcher& operator=(const InterruptWatcher&) = delete;

 private:
  void Run();

  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// Routes interrupts to `handler` while alive. It runs on the watcher
// thread, must not block, and may use what the scope owns: the destructor
// waits for a handler that is running. `count` is 1 for the first
// interrupt, 2 for the second, ...
class ScopedInterruptHandler {
 public:
  explicit ScopedInterruptHandler(std::function<void(int count)> handler);
  ~ScopedInterruptHandler();
  ScopedInterruptHandler(const ScopedInterruptHandler&) = delete;
  ScopedInterruptHandler& operator=(const ScopedInterruptHandler&) = delete;
};

}  // namespace gistream::client
