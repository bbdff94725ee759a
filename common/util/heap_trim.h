// Returning freed heap memory to the operating system (issue 30, item 4).
//
// glibc keeps what a scene's import and CPU copy freed in its arenas: after
// an unload the process's RSS stays where the load took it, and the memory
// budget (which counts what is live) and the machine (which counts RSS)
// disagree. HeapTrimmer returns it: once asked (a scene dropped, a load
// ended), and once `free_above` bytes or more lie free in the arenas, it
// calls malloc_trim, which unmaps the free pages of every arena. Elsewhere
// than glibc it does nothing.
#pragma once

#include <chrono>
#include <cstdint>

namespace gistream {

// Bytes free in the allocator's arenas (glibc's mallinfo2 fordblks, every
// arena); 0 where the allocator does not say.
uint64_t FreeHeapBytes();

// Returns the arenas' free pages to the system (malloc_trim(0)); false
// where nothing was returned or the allocator cannot.
bool TrimHeap();

// When to trim: Request() after memory was freed (or soon will be: the
// arguments of a request are freed after it returns), Poll() from a loop
// that runs often. Single-threaded: its owner's thread only.
class HeapTrimmer {
 public:
  using Clock = std::chrono::steady_clock;
  explicit HeapTrimmer(uint64_t free_above = 64ull << 20,
                       Clock::duration delay = std::chrono::milliseconds(500))
      : free_above_(free_above), delay_(delay) {}

  // Trim at `now` + delay (a later request moves it).
  void Request(Clock::time_point now) {
    due_ = now + delay_;
    pending_ = true;
  }
  // When Poll wants to run next; Clock::time_point::max() when nothing is
  // pending.
  Clock::time_point due() const { return pending_ ? due_ : Clock::time_point::max(); }
  // Trims if a request is due and enough is free; true when it trimmed.
  bool Poll(Clock::time_point now);

  uint64_t trims() const { return trims_; }

 private:
  uint64_t free_above_;
  Clock::duration delay_;
  Clock::time_point due_{};
  bool pending_ = false;
  uint64_t trims_ = 0;
};

}  // namespace gistream
