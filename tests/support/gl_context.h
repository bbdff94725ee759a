// A current EGL context for tests that issue GL themselves (Mesa llvmpipe
// when the machine has no GPU; never skipped).
#pragma once

#include <memory>

#include <gtest/gtest.h>

#include "gl/egl_context.h"

namespace gistream::testing {

// A new context, made current on this thread; null (and the test has
// failed, naming why) when either step fails.
inline std::unique_ptr<gl::EglContext> CurrentGlContext() {
  auto context = gl::EglContext::Create(-1);
  EXPECT_TRUE(context.ok()) << context.status();
  if (!context.ok()) return nullptr;
  const absl::Status current = (*context)->MakeCurrent();
  EXPECT_TRUE(current.ok()) << current;
  return current.ok() ? *std::move(context) : nullptr;
}

// A fixture holding such a context for each test.
class GlContextTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(context_ = CurrentGlContext()); }

  std::unique_ptr<gl::EglContext> context_;
};

}  // namespace gistream::testing
