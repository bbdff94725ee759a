#include "gl/fault_injection.h"

#include <atomic>
#include <mutex>
#include <system_error>

namespace gistream::gl {
namespace {

// Never destroyed: render threads of engines that outlive main() (a test
// fixture's static engine) still check for faults during static
// destruction.
std::mutex& Mutex() {
  static auto* mutex = new std::mutex;
  return *mutex;
}
std::filesystem::path& Directory() {
  static auto* dir = new std::filesystem::path;
  return *dir;
}
std::atomic<bool> enabled{false};  // constant-initialised, trivially destroyed

// Removes `name` from the fault directory; true when it was there.
bool Take(const char* name) {
  if (!enabled.load(std::memory_order_relaxed)) return false;
  std::lock_guard lock(Mutex());
  if (Directory().empty()) return false;
  std::error_code error;
  return std::filesystem::remove(Directory() / name, error);
}

}  // namespace

void SetFaultDirectory(const std::filesystem::path& dir) {
  std::lock_guard lock(Mutex());
  Directory() = dir;
  enabled = !dir.empty();
}

InjectedReset TakeInjectedReset() {
  if (Take("gpu_reset_fail")) return InjectedReset::kResetAndFailRecovery;
  if (Take("gpu_reset")) return InjectedReset::kReset;
  return InjectedReset::kNone;
}

GLenum AllocationError() {
  const GLenum error = glGetError();
  if (Take("gpu_oom")) return GL_OUT_OF_MEMORY;
  return error;
}

}  // namespace gistream::gl
