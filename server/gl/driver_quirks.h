// Driver workarounds in one place (after Magnum's "driver workarounds"
// list): detected once per context from GL_RENDERER / GL_VENDOR, read by
// the code that needs them, each with the reason it exists.
#pragma once

#include <string>

namespace gistream::gl {

struct DriverQuirks {
  // Mesa's llvmpipe records commands and runs them at the next flush or
  // wait: without a glFlush after each GPU stage, a stage's work runs
  // inside whatever waits next (often a CPU stage) and its timer query
  // reads the wrong time. Hardware drivers submit on their own.
  bool flush_after_gpu_stage = false;

  // From the strings of the current context.
  static DriverQuirks Detect(const std::string& renderer, const std::string& vendor);
};

// The quirks of the context current on this thread (set by
// EglContext::MakeCurrent; all false where no context was made current).
const DriverQuirks& CurrentQuirks();
void SetCurrentQuirks(const DriverQuirks& quirks);

}  // namespace gistream::gl
