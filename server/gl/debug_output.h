// KHR_debug: routes driver messages to our log instead of polling
// glGetError after each call. Enabled in debug builds and with
// GISTREAM_GL_DEBUG=1 (which the test binaries set: a GL error during a
// test fails it, tests/support/gl_error_listener.cpp).
#pragma once

#include <cstdint>

namespace gistream::gl {
void InstallDebugOutput();
// GL_DEBUG_TYPE_ERROR messages seen by any context of the process so far.
uint64_t DebugErrorCount();
}  // namespace gistream::gl
