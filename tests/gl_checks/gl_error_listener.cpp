// Compiled into each test binary that renders (tests/CMakeLists.txt), not
// into the support library, so its registration is never dropped.
#include "gl_checks/gl_error_listener.h"

#include <atomic>
#include <cstdlib>

#include <gtest/gtest.h>

#include "gl/debug_output.h"

namespace gistream::testing {
namespace {

std::atomic<bool> errors_allowed{false};

class GlErrorListener : public ::testing::EmptyTestEventListener {
  void OnTestStart(const ::testing::TestInfo& /*test*/) override {
    errors_allowed = false;
    at_start_ = gl::DebugErrorCount();
  }
  // Failures raised here belong to the test that just ran (googletest's
  // sample10 does the same for leaks). End events go to listeners in
  // reverse order, so this one, appended after the result printer, runs
  // before it and the printed verdict includes them.
  void OnTestEnd(const ::testing::TestInfo& /*test*/) override {
    const uint64_t errors = gl::DebugErrorCount() - at_start_;
    if (!errors_allowed) {
      EXPECT_EQ(errors, 0u) << "GL errors were reported during this test (see the "
                               "'GL debug' lines in its log)";
    }
  }
  uint64_t at_start_ = 0;
};

const bool kInstalled = [] {
  // KHR_debug output on in every context of this process (gl/debug_output.h).
  setenv("GISTREAM_GL_DEBUG", "1", /*overwrite=*/1);
  ::testing::UnitTest::GetInstance()->listeners().Append(new GlErrorListener);
  return true;
}();

}  // namespace

void AllowGlErrorsInThisTest() { errors_allowed = true; }

}  // namespace gistream::testing
