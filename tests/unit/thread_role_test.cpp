// ThreadRole (common/util/thread_role.h) and Mutex (common/util/mutex.h):
// the run-time half of the engine's ownership checks. The compile-time
// half is the thread_safety_analysis test (tests/thread_safety/). Also in
// thread_tests, under ThreadSanitizer, which must see Mutex's locking.
#include "util/thread_role.h"

#include "util/mutex.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace gistream {
namespace thread_role_test {

TEST(ThreadRole, AnyThreadMayAssertBeforeTheRoleIsBound) {
  ThreadRole role("test role");
  role.Assert();
  std::thread([&] { role.Assert(); }).join();
}

TEST(ThreadRole, TheBoundThreadPassesItsAssert) {
  ThreadRole role("test role");
  std::thread([&] {
    role.Bind();
    role.Assert();
    role.Assert();
  }).join();
}

TEST(ThreadRoleDeathTest, AnotherThreadAbortsNamingTheRole) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        ThreadRole role("render thread");
        std::thread([&] { role.Bind(); }).join();
        role.Assert();  // this thread is not the one bound
      },
      "render thread state touched off its thread");
}

// Four threads add to one counter under the Mutex: every increment lands
// (and ThreadSanitizer, in thread_tests, reports no race).
TEST(Mutex, GuardsACounterAcrossThreads) {
  struct Counter {
    Mutex mutex;
    int value ABSL_GUARDED_BY(mutex) = 0;
  } counter;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 10000; ++i) {
        MutexLock lock(counter.mutex);
        ++counter.value;
      }
    });
  }
  for (std::thread& t : threads) t.join();
  MutexLock lock(counter.mutex);
  EXPECT_EQ(counter.value, 40000);
}

}  // namespace thread_role_test
}  // namespace gistream
