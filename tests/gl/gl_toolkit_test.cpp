// The GL layer's checks: KHR_debug errors are counted (and fail the test
// that caused them, gl_checks/gl_error_listener.cpp), driver quirks are
// detected from the renderer string, Program::Location of a name that is
// not in the program is -1.
#include <gtest/gtest.h>

#include "gl/debug_output.h"
#include "gl/driver_quirks.h"
#include "gl/gl.h"
#include "gl/program.h"
#include "gl_checks/gl_error_listener.h"
#include "support/gl_context.h"

namespace gistream {
namespace gl_toolkit_test {

TEST(GlDebug, AnInvalidCallIsCountedAsAnError) {
  testing::AllowGlErrorsInThisTest();  // provoked on purpose
  const auto context = testing::CurrentGlContext();
  ASSERT_TRUE(context);
  gl::InstallDebugOutput();  // GISTREAM_GL_DEBUG=1 in test binaries
  const uint64_t before = gl::DebugErrorCount();
  glBindBuffer(GL_ARRAY_BUFFER, 0x7fffffff);  // not a name from glCreateBuffers: INVALID_OPERATION
  EXPECT_EQ(glGetError(), GLenum(GL_INVALID_OPERATION));
  EXPECT_GE(gl::DebugErrorCount(), before + 1);
  context->ReleaseCurrent();
}

TEST(GlDriverQuirks, LlvmpipeFlushesAfterEachStageHardwareDoesNot) {
  EXPECT_TRUE(
      gl::DriverQuirks::Detect("llvmpipe (LLVM 15.0.6, 256 bits)", "Mesa").flush_after_gpu_stage);
  EXPECT_FALSE(gl::DriverQuirks::Detect("NVIDIA H200/PCIe/SSE2", "NVIDIA Corporation")
                   .flush_after_gpu_stage);
}

TEST(GlDriverQuirks, MakeCurrentDetectsTheContextsDriver) {
  const auto context = testing::CurrentGlContext();
  ASSERT_TRUE(context);
  const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  EXPECT_EQ(gl::CurrentQuirks().flush_after_gpu_stage,
            renderer.find("llvmpipe") != std::string::npos)
      << renderer;
  context->ReleaseCurrent();
}

TEST(GlProgram, UnknownUniformHasNoLocation) {
  const auto context = testing::CurrentGlContext();
  ASSERT_TRUE(context);
  {
    auto program = gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                       {GL_FRAGMENT_SHADER, "render/tonemap.frag.glsl"}});
    ASSERT_TRUE(program.ok()) << program.status();
    EXPECT_EQ(program->Location("uNoSuchUniformAnywhere"), -1);
    program->SetOptional("uNoSuchUniformAnywhere", 1.0f);  // silently nothing
  }
  context->ReleaseCurrent();
}

}  // namespace gl_toolkit_test
}  // namespace gistream
