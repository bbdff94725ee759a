#include "gl/memory_info.h"

#include <cstring>

#include "gl/gl.h"

namespace gistream::gl {
namespace {
// Values from the extension specifications (not in glcorearb.h).
constexpr GLenum kNvxTotalAvailableMemory =
    0x9048;  // GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX, kB
constexpr GLenum kNvxCurrentAvailableVidmem =
    0x9049;  // GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX, kB
constexpr GLenum kAtiTextureFreeMemory = 0x87FC;  // TEXTURE_FREE_MEMORY_ATI, 4 ints, [0] kB

uint64_t Kib(GLint kib) { return kib > 0 ? uint64_t(kib) * 1024 : 0; }
}  // namespace

GpuMemoryQuery::GpuMemoryQuery() {
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i) {
    const auto* name = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
    if (name == nullptr) continue;
    if (std::strcmp(name, "GL_NVX_gpu_memory_info") == 0) nvx_ = true;
    if (std::strcmp(name, "GL_ATI_meminfo") == 0) ati_ = true;
  }
}

GpuMemoryInfo GpuMemoryQuery::Query() const {
  GpuMemoryInfo info;
  if (nvx_) {
    GLint total = 0, available = 0;
    glGetIntegerv(kNvxTotalAvailableMemory, &total);
    glGetIntegerv(kNvxCurrentAvailableVidmem, &available);
    info.total_bytes = Kib(total);
    info.available_bytes = Kib(available);
  } else if (ati_) {
    GLint free[4] = {0, 0, 0, 0};
    glGetIntegerv(kAtiTextureFreeMemory, free);
    info.available_bytes = Kib(free[0]);
  }
  return info;
}

}  // namespace gistream::gl
