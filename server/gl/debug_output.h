// KHR_debug: routes driver messages to our log instead of polling
// glGetError after each call. Enabled in debug builds and with
// GISTREAM_GL_DEBUG=1.
#pragma once

namespace gistream::gl {
void InstallDebugOutput();
}  // namespace gistream::gl
