// Timing of one named stage of one frame.
#pragma once

#include <string>

namespace gistream {

struct StageTiming {
  std::string name;
  double cpu_ms = 0.0;
  double gpu_ms = 0.0;
  bool skipped = false;    // the change did not need this stage
  bool cpu_stage = false;  // runs on the CPU; gpu_ms is 0
};

}  // namespace gistream
