// CPU texel lookups under a glTF sampler (scene/texture_lookup.h), the
// path tracer's and implicit_visibility's: closed forms on a 4 x 1 image
// of texels 0, 1/3, 2/3, 1 (linear, 8-bit: 0, 85, 170, 255).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "scene/texture_lookup.h"

namespace gistream {
namespace texture_lookup_test {

Image Ramp() {
  Image image;
  image.width = 4;
  image.height = 1;
  image.srgb = false;
  for (uint8_t v : {0, 85, 170, 255}) image.pixels8.insert(image.pixels8.end(), {v, v, v, 255});
  return image;
}

TextureSampler Wrap(int s) {
  TextureSampler t;
  t.wrap_s = s;
  return t;
}

TEST(TextureLookup, WrapTexelFollowsGl) {
  // GL 4.6 8.14.2: repeat is i mod n; clamp to edge stays in [0, n - 1];
  // mirrored repeat runs 0..n-1 then n-1..0.
  const int n = 4;
  EXPECT_EQ(WrapTexel(5, n, TextureSampler::kRepeat), 1);
  EXPECT_EQ(WrapTexel(-1, n, TextureSampler::kRepeat), 3);
  EXPECT_EQ(WrapTexel(-1, n, TextureSampler::kClampToEdge), 0);
  EXPECT_EQ(WrapTexel(9, n, TextureSampler::kClampToEdge), 3);
  EXPECT_EQ(WrapTexel(4, n, TextureSampler::kMirroredRepeat), 3);
  EXPECT_EQ(WrapTexel(7, n, TextureSampler::kMirroredRepeat), 0);
  EXPECT_EQ(WrapTexel(8, n, TextureSampler::kMirroredRepeat), 0);
  EXPECT_EQ(WrapTexel(-1, n, TextureSampler::kMirroredRepeat), 0);
  EXPECT_EQ(WrapTexel(-2, n, TextureSampler::kMirroredRepeat), 1);
}

TEST(TextureLookup, NearestReadsTheWrappedTexel) {
  const Image ramp = Ramp();
  TextureSampler nearest;
  nearest.mag_filter = TextureSampler::kNearest;
  const auto at = [&](float u, TextureSampler t) {
    t.mag_filter = TextureSampler::kNearest;
    return SampleImage(ramp, {u, 0.5f}, t).r;
  };
  EXPECT_NEAR(SampleImage(ramp, {0.3f, 0.5f}, nearest).r, 85.0f / 255.0f, 1e-6f);
  // u = 1.3: texel 5.2 -> repeat 1, clamp 3, mirror 2.
  EXPECT_NEAR(at(1.3f, Wrap(TextureSampler::kRepeat)), 85.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(at(1.3f, Wrap(TextureSampler::kClampToEdge)), 1.0f, 1e-6f);
  EXPECT_NEAR(at(1.3f, Wrap(TextureSampler::kMirroredRepeat)), 170.0f / 255.0f, 1e-6f);
  // Far out, the periods are taken off first: u = 1e6 + 0.3.
  EXPECT_NEAR(at(1000000.3f, Wrap(TextureSampler::kRepeat)), 85.0f / 255.0f, 1e-6f);
  // kNearest whatever the sampler's filter.
  EXPECT_NEAR(SampleImage(ramp, {0.3f, 0.5f}, TextureSampler{}, TextureFilter::kNearest).r,
              85.0f / 255.0f, 1e-6f);
}

TEST(TextureLookup, BilinearBetweenTexelCentres) {
  const Image ramp = Ramp();
  // u = 0.5: texel coordinate 2, halfway between texels 1 and 2.
  EXPECT_NEAR(SampleImage(ramp, {0.5f, 0.5f}, TextureSampler{}).r, 127.5f / 255.0f, 1e-6f);
  // u = 0: halfway between texel -1 and 0: repeat blends texel 3 (1.0)
  // and 0 (0.0), clamp reads texel 0 twice, mirror texel 0 twice.
  EXPECT_NEAR(SampleImage(ramp, {0.0f, 0.5f}, Wrap(TextureSampler::kRepeat)).r, 0.5f, 1e-6f);
  EXPECT_NEAR(SampleImage(ramp, {0.0f, 0.5f}, Wrap(TextureSampler::kClampToEdge)).r, 0.0f, 1e-6f);
  EXPECT_NEAR(SampleImage(ramp, {0.0f, 0.5f}, Wrap(TextureSampler::kMirroredRepeat)).r, 0.0f,
              1e-6f);
}

TEST(TextureLookup, SrgbFloatAndBadInput) {
  Image srgb = Ramp();
  srgb.srgb = true;
  TextureSampler nearest;
  nearest.mag_filter = TextureSampler::kNearest;
  // sRGB 170/255 = 0.6667 is linear ((0.6667 + 0.055) / 1.055)^2.4 = 0.402.
  EXPECT_NEAR(SampleImage(srgb, {0.6f, 0.5f}, nearest).r, 0.4020f, 1e-3f);
  Image hdr;
  hdr.width = hdr.height = 1;
  hdr.is_float = true;
  hdr.pixelsf = {7.5f, 0.0f, 0.0f, 1.0f};
  EXPECT_EQ(SampleImage(hdr, {0.2f, 0.7f}, TextureSampler{}).r, 7.5f);
  // Non-finite coordinates read as 0; an empty image is white.
  EXPECT_TRUE(std::isfinite(
      SampleImage(Ramp(), {std::numeric_limits<float>::quiet_NaN(), 0.5f}, nearest).r));
  EXPECT_EQ(SampleImage(Image{}, {0.5f, 0.5f}, nearest), glm::vec3(1.0f));
}

}  // namespace texture_lookup_test
}  // namespace gistream
