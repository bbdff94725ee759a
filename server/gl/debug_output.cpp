#include "gl/debug_output.h"

#include <cstdlib>
#include <string>

#include "gl/gl.h"
#include "util/log.h"

namespace gistream::gl {
namespace {
void OnMessage(GLenum /*source*/, GLenum type, GLuint id, GLenum severity,
                          GLsizei length, const GLchar* message, const void* /*user*/) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
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

}  // namespace gistream::gl
