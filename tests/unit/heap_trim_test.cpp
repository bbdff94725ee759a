// HeapTrimmer (issue 30, item 4): freed heap goes back to the system once
// asked and due, and only when enough of it is free.
#include "util/heap_trim.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <vector>

#include "util/process_stats.h"

namespace gistream {
namespace heap_trim_test {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitizerAllocator = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
constexpr bool kSanitizerAllocator = true;
#else
constexpr bool kSanitizerAllocator = false;
#endif
#else
constexpr bool kSanitizerAllocator = false;
#endif

using Clock = HeapTrimmer::Clock;
constexpr uint64_t kMiB = 1ull << 20;

// 64 KiB blocks (below glibc's mmap threshold: they live in the heap), each
// followed by a small block that stays: freeing the large ones leaves holes
// glibc keeps, not a top it would release by itself.
struct Fragmented {
  std::vector<std::unique_ptr<char[]>> large, small;
  explicit Fragmented(uint64_t bytes) {
    for (uint64_t i = 0; i < bytes / (64 * 1024); ++i) {
      large.emplace_back(new char[64 * 1024]);
      std::memset(large.back().get(), int(i), 64 * 1024);  // resident
      small.emplace_back(new char[64]);
    }
  }
  void FreeLarge() { large.clear(); }
};

TEST(HeapTrimmer, NothingPendingIsNeverDue) {
  HeapTrimmer trimmer(0);
  EXPECT_EQ(trimmer.due(), Clock::time_point::max());
  EXPECT_FALSE(trimmer.Poll(Clock::now()));
  EXPECT_EQ(trimmer.trims(), 0u);
}

TEST(HeapTrimmer, TrimsOnceWhenDueAndNotBefore) {
  HeapTrimmer trimmer(0, std::chrono::seconds(1));
  const auto t0 = Clock::now();
  trimmer.Request(t0);
  EXPECT_EQ(trimmer.due(), t0 + std::chrono::seconds(1));
  EXPECT_FALSE(trimmer.Poll(t0 + std::chrono::milliseconds(999)));
  EXPECT_TRUE(trimmer.Poll(t0 + std::chrono::seconds(1)));
  EXPECT_EQ(trimmer.trims(), 1u);
  // One request, one trim.
  EXPECT_FALSE(trimmer.Poll(t0 + std::chrono::seconds(2)));
  EXPECT_EQ(trimmer.due(), Clock::time_point::max());
}

TEST(HeapTrimmer, ALaterRequestMovesTheTrim) {
  HeapTrimmer trimmer(0, std::chrono::seconds(1));
  const auto t0 = Clock::now();
  trimmer.Request(t0);
  trimmer.Request(t0 + std::chrono::milliseconds(800));
  EXPECT_FALSE(trimmer.Poll(t0 + std::chrono::seconds(1)));
  EXPECT_TRUE(trimmer.Poll(t0 + std::chrono::milliseconds(1800)));
}

TEST(HeapTrimmer, FreedHeapGoesBackToTheSystem) {
  if (kSanitizerAllocator) GTEST_SKIP() << "a sanitizer's allocator replaces glibc's arenas";
  Fragmented heap(48 * kMiB);
  const uint64_t held = ReadProcessStats().rss_bytes;
  heap.FreeLarge();
  // glibc keeps the holes: at least 40 of the 48 MiB stay free in its
  // arenas, and resident.
  ASSERT_GE(FreeHeapBytes(), 40 * kMiB);
  const uint64_t before = ReadProcessStats().rss_bytes;
  ASSERT_GE(before + 8 * kMiB, held);
  // Asked with a threshold above what is free: nothing happens.
  HeapTrimmer too_little(FreeHeapBytes() + 64 * kMiB, std::chrono::milliseconds(0));
  too_little.Request(Clock::now());
  EXPECT_FALSE(too_little.Poll(Clock::now()));
  // Asked with 32 MiB: at least 32 of the 48 MiB leave the process.
  HeapTrimmer trimmer(32 * kMiB, std::chrono::milliseconds(0));
  trimmer.Request(Clock::now());
  EXPECT_TRUE(trimmer.Poll(Clock::now()));
  const uint64_t after = ReadProcessStats().rss_bytes;
  EXPECT_LE(after + 32 * kMiB, before)
      << "RSS " << before / kMiB << " -> " << after / kMiB << " MiB";
}

}  // namespace heap_trim_test
}  // namespace gistream
