#include "gl/debug_output.h"

#include <atomic>
#include <cstdlib>
#include <string>

#include "gl/gl.h"
#include "util/log.h"

namespace gistream::gl {
namespace {
std::atomic<uint64_t> error_count{0};

void OnMessage(GLenum /*source*/, GLenum type, GLuint id, GLenum severity, GLsizei length,
               const GLchar* message, const void* /*user*/) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  if (type == GL_DEBUG_TYPE_ERROR) error_count.fetch_add(1, std::memory_order_relaxed);
  const LogLevel level = type == GL_DEBUG_TYPE_ERROR ? LogLevel::kError : LogLevel::kWarning;
  Log(level, "GL debug [" + std::to_string(id) + "]: " + std::string(message, size_t(length)));
}
}  // namespace

void InstallDebugOutput() {
#ifdef NDEBUG
  const char* env = std::getenv("GISTREAM_GL_DEBUG");
  if (env == nullptr || std::string(env) != "1") return;
#endif
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(OnMessage, nullptr);
}

uint64_t DebugErrorCount() { return error_count.load(std::memory_order_relaxed); }

}  // namespace gistream::gl
