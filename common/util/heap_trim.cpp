#include "util/heap_trim.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace gistream {

uint64_t FreeHeapBytes() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 info = mallinfo2();
  return uint64_t(info.fordblks);
#else
  return 0;
#endif
}

bool TrimHeap() {
#if defined(__GLIBC__)
  return malloc_trim(0) != 0;
#else
  return false;
#endif
}

bool HeapTrimmer::Poll(Clock::time_point now) {
  if (!pending_ || now < due_) return false;
  pending_ = false;
  if (FreeHeapBytes() < free_above_) return false;
  TrimHeap();
  trims_ += 1;
  return true;
}

}  // namespace gistream
