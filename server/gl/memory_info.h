// GPU memory as the driver reports it, where it does: NVIDIA's
// GL_NVX_gpu_memory_info (total and currently available video memory) or
// AMD's GL_ATI_meminfo (free texture memory only). Render thread (needs the
// current context).
#pragma once

#include <cstdint>

namespace gistream::gl {

struct GpuMemoryInfo {
  uint64_t total_bytes = 0;      // 0: not reported
  uint64_t available_bytes = 0;  // 0: not reported
};

class GpuMemoryQuery {
 public:
  // Looks for the extensions in the current context.
  GpuMemoryQuery();
  bool supported() const { return nvx_ || ati_; }
  GpuMemoryInfo Query() const;

 private:
  bool nvx_ = false;
  bool ati_ = false;
};

}  // namespace gistream::gl
