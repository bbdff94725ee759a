// ThreadRole (common/util/thread_role.h): the run-time half of the render
// thread's ownership checks. The compile-time half is the
// thread_safety_analysis test (tests/thread_safety/).
#include "util/thread_role.h"

#include <gtest/gtest.h>

#include <thread>

namespace gistream {
namespace {

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

}  // namespace
}  // namespace gistream
