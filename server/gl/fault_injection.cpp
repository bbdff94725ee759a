#include "gl/fault_injection.h"

#include <mutex>
#include <system_error>

namespace gistream::gl {
namespace {

std::mutex& Mutex() {
  static std::mutex mutex;
  return mutex;
}
std::filesystem::path& Directory() {
  static std::filesystem::path dir;
  return dir;
}

// Removes `name` from the fault directory; true when it was there.
bool Take(const char* name) {
  std::lock_guard lock(Mutex());
  if (Directory().empty()) return false;
  std::error_code error;
  return std::filesystem::remove(Directory() / name, error);
}

}  // namespace

void SetFaultDirectory(const std::filesystem::path& dir) {
  std::lock_guard lock(Mutex());
  Directory() = dir;
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
