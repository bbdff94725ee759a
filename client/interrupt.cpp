#include "interrupt.h"

#include <pthread.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <ctime>
#include <mutex>

namespace gistream::client {
namespace {

std::mutex g_mutex;
std::function<void(int)> g_handler;  // guarded by g_mutex
int g_count = 0;                     // guarded by g_mutex

sigset_t InterruptSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

}  // namespace

InterruptWatcher::InterruptWatcher() {
  const sigset_t set = InterruptSignals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  thread_ = std::thread([this] { Run(); });
}

InterruptWatcher::~InterruptWatcher() {
  stop_ = true;
  thread_.join();
}

void InterruptWatcher::Run() {
  const sigset_t set = InterruptSignals();
  // sigtimedwait rather than sigwait so that the destructor can stop us.
  const timespec poll{0, 100'000'000};
  while (!stop_) {
    const int signal = sigtimedwait(&set, nullptr, &poll);
    if (signal < 0) continue;  // EAGAIN (timeout) or EINTR
    std::lock_guard lock(g_mutex);
    if (!g_handler) std::_Exit(128 + signal);
    g_handler(++g_count);
  }
}

ScopedInterruptHandler::ScopedInterruptHandler(std::function<void(int)> handler) {
  std::lock_guard lock(g_mutex);
  g_handler = std::move(handler);
  g_count = 0;
}

ScopedInterruptHandler::~ScopedInterruptHandler() {
  std::lock_guard lock(g_mutex);
  g_handler = nullptr;
}

}  // namespace gistream::client
