// Compute dispatch with group counts derived from invocation counts, so
// no solver keeps its own Groups() helper.
#pragma once

#include <cstddef>

#include "gl/gl.h"

namespace gistream::gl {

// Work groups of `local_size` invocations that cover `invocations` (none
// for none: a dispatch of zero groups is valid and does nothing).
inline GLuint GroupCount(size_t invocations, size_t local_size) {
  return GLuint((invocations + local_size - 1) / local_size);
}

// Dispatches the bound compute program over x * y * z invocations with the
// shader's local size (local_x, local_y, local_z).
inline void Dispatch(size_t x, size_t local_x, size_t y = 1, size_t local_y = 1, size_t z = 1,
                     size_t local_z = 1) {
  glDispatchCompute(GroupCount(x, local_x), GroupCount(y, local_y), GroupCount(z, local_z));
}

}  // namespace gistream::gl
