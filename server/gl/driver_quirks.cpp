#include "gl/driver_quirks.h"

namespace gistream::gl {
namespace {
thread_local DriverQuirks current_quirks;
}  // namespace

DriverQuirks DriverQuirks::Detect(const std::string& renderer, const std::string& /*vendor*/) {
  DriverQuirks quirks;
  const bool llvmpipe = renderer.find("llvmpipe") != std::string::npos ||
                        renderer.find("softpipe") != std::string::npos;
  quirks.flush_after_gpu_stage = llvmpipe;
  return quirks;
}

const DriverQuirks& CurrentQuirks() { return current_quirks; }
void SetCurrentQuirks(const DriverQuirks& quirks) { current_quirks = quirks; }

}  // namespace gistream::gl
