// Issue 13, finding 3 ("+Inf out of finite input"), second half: whatever
// a solver writes, a frame with NaN or Inf never leaves the server. The
// engine counts non-finite HDR pixels in the tone-map pass (JPEG/PNG) and
// scans the float readback (EXR); this checks the tone-map counter on a
// G-buffer seeded with known bad pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "gl/gl.h"
#include "render/gbuffer.h"
#include "render/view_passes.h"
#include "support/gl_context.h"

namespace gistream {
namespace finite_frames_test {

TEST(FiniteFrames, ToneMapCountsNonFinitePixels) {
  const auto context = testing::CurrentGlContext();
  ASSERT_TRUE(context);
  {
    auto passes = ViewPasses::Create();
    ASSERT_TRUE(passes.ok()) << passes.status();
    GBuffer gbuffer;
    constexpr uint32_t kSize = 8;
    ASSERT_TRUE(gbuffer.Resize(kSize, kSize).ok());
    std::vector<float> hdr(kSize * kSize * 4, 0.5f);
    const auto set = [&](int pixel, int channel, float v) {
      hdr[size_t(pixel) * 4 + size_t(channel)] = v;
    };

    // Finite, including the largest float (which the exposure pushes to
    // +Inf only after the count): nothing counted.
    set(3, 0, std::numeric_limits<float>::max());
    glTextureSubImage2D(gbuffer.hdr(), 0, 0, 0, kSize, kSize, GL_RGBA, GL_FLOAT, hdr.data());
    passes->Tonemap(gbuffer, 0.0f);
    (void)passes->ReadLdr(gbuffer);
    EXPECT_EQ(passes->NonFinitePixels(), 0u);

    // Three bad pixels (+Inf, -Inf in another channel, NaN); a bad alpha
    // is no radiance and is not counted.
    set(0, 0, std::numeric_limits<float>::infinity());
    set(9, 2, -std::numeric_limits<float>::infinity());
    set(20, 1, std::nanf(""));
    set(30, 3, std::numeric_limits<float>::infinity());
    glTextureSubImage2D(gbuffer.hdr(), 0, 0, 0, kSize, kSize, GL_RGBA, GL_FLOAT, hdr.data());
    passes->Tonemap(gbuffer, 0.0f);
    const std::vector<uint8_t> ldr = passes->ReadLdr(gbuffer);
    EXPECT_EQ(passes->NonFinitePixels(), 3u);
    ASSERT_EQ(ldr.size(), size_t(kSize) * kSize * 4);

    // The counter is reset by each pass.
    hdr.assign(hdr.size(), 0.25f);
    glTextureSubImage2D(gbuffer.hdr(), 0, 0, 0, kSize, kSize, GL_RGBA, GL_FLOAT, hdr.data());
    passes->Tonemap(gbuffer, 0.0f);
    (void)passes->ReadLdr(gbuffer);
    EXPECT_EQ(passes->NonFinitePixels(), 0u);
  }
  context->ReleaseCurrent();
}

}  // namespace finite_frames_test
}  // namespace gistream
