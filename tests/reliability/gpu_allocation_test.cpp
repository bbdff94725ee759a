// Issue 13, finding 6 (in part): a G-buffer the GPU cannot hold aborted the
// process (GS_CHECK on framebuffer completeness; GL_OUT_OF_MEMORY was not
// looked at). It is RESOURCE_EXHAUSTED for that session; the server goes on.
#include <gtest/gtest.h>

#include "reliability/reliability_fixture.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace {

TEST(GpuAllocation, OversizedGBufferIsResourceExhaustedAndTheEngineGoesOn) {
  // The operator allows frames wider than any GPU's largest texture
  // (llvmpipe 16384, current NVIDIA 32768).
  EngineOptions options;
  options.scene_dir = SceneDir();
  options.max_width = 1'000'000;
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  auto info = (*engine)->LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  ASSERT_TRUE(info.ok()) << info.status();

  RenderRequest wide = Request(info->id, "direct");
  wide.width = 1'000'000;
  wide.height = 1;
  EXPECT_STATUS(StatusOf((*engine)->Render(wide)), kResourceExhausted,
                "width x height: 1000000x1 is not a texture size this GPU offers");

  // The same engine renders the next, normal frame.
  auto frame = (*engine)->Render(Request(info->id, "direct"));
  ASSERT_TRUE(frame.ok()) << frame.status();
  const testing::FloatImage image = testing::DecodeExr(*frame);
  EXPECT_EQ(image.non_finite(), 0u);
  EXPECT_GT(testing::ImageMean(image).x, 0.0);
  (*engine)->Shutdown();
}

}  // namespace
}  // namespace gistream::reliability
