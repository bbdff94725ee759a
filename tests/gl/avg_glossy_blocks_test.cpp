// `avg` on a flat glossy face: interleaved sampling lights each pixel of a
// 4 x 4 tile with a different sixteenth of the VPLs, and a roughness-0.3
// lobe shows a single VPL's highlight on a few pixels only; the filter
// must reconstruct it without the 4 x 4 blocks a box over one sample per
// subset makes (shaders/avg/filter.frag.glsl, avg/receiver.glsl's
// VplGlossyResponse). llvmpipe-sized: 64 x 64.
#include <cmath>

#include <gtest/gtest.h>

#include "support/gltf_builder.h"
#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace avg_glossy_blocks_test {

using testing::FloatImage;
using testing::GltfBuilder;

constexpr uint32_t kSize = 64;

// A gold wall (metallic 1, roughness 0.3, the glossy_box cube's material)
// filling the view, a grey floor in front of it lit by a spot from above.
// The camera looks straight at the wall from 3 m: every pixel is the same
// flat glossy face; its lower half reflects the lit floor, whose VPLs near
// the wall's foot are the close ones whose highlights are smallest.
std::string LoadWallScene() {
  GltfBuilder b;
  const int gold = b.AddMaterial("gold", {1.0f, 0.78f, 0.34f});
  b.SetMetallicRoughness(gold, 1.0f, 0.3f);
  const int grey = b.AddMaterial("grey", {0.6f, 0.6f, 0.6f});
  b.AddQuad("wall", {0, 1.5f, 0}, {2, 0, 0}, {0, 1.5f, 0}, gold);
  b.AddQuad("floor", {0, 0, 1.5f}, {0, 0, 1.5f}, {2, 0, 0}, grey);
  b.AddSpotLightDown("spot", {0, 2.5f, 0.8f}, {1, 1, 1}, 40.0f, 0.5f, 0.7f);
  b.AddCamera("camera", {0, 1.0f, 3.0f}, {0, 0, -1}, {0, 1, 0}, 0.6f);
  auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(b.ToJson()));
  EXPECT_TRUE(info.ok()) << info.status();
  return info.ok() ? info->id : "";
}

float Luminance(const FloatImage& image, int x, int y) {
  const glm::vec3 c = image.at(x, y);
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

// The mirrored case (issue 29, item 6): a grey wall filling the view, a
// gold floor in front of it lit by a point light over the floor: the
// floor's VPLs reflect through the gold's lobe, each a narrow spot on the
// Lambertian wall.
std::string LoadGoldFloorScene() {
  GltfBuilder b;
  const int gold = b.AddMaterial("gold", {1.0f, 0.78f, 0.34f});
  b.SetMetallicRoughness(gold, 1.0f, 0.3f);
  const int grey = b.AddMaterial("grey", {0.6f, 0.6f, 0.6f});
  b.AddQuad("wall", {0, 1.5f, 0}, {2, 0, 0}, {0, 1.5f, 0}, grey);
  b.AddQuad("floor", {0, 0, 1.5f}, {0, 0, 1.5f}, {2, 0, 0}, gold);
  b.AddPointLight("lamp", {0, 1.2f, 2.0f}, {1, 1, 1}, 20.0f);
  b.AddCamera("camera", {0, 1.5f, 3.0f}, {0, 0, -1}, {0, 1, 0}, 0.6f);
  auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(b.ToJson()));
  EXPECT_TRUE(info.ok()) << info.status();
  return info.ok() ? info->id : "";
}

// Over rows [y0, y1) less a 3-pixel border, in luminance and relative to
// their mean: the mean absolute second difference and the largest jump
// between neighbours, along x and y.
struct Roughness {
  double mean = 0.0, second_difference = 0.0, max_jump = 0.0;
};
Roughness Measure(const FloatImage& image, int y0, int y1) {
  const int size = image.width;
  double sum = 0.0, second = 0.0, jump = 0.0;
  int pixels = 0, pairs = 0;
  for (int y = std::max(y0, 3); y < std::min(y1, size - 3); ++y) {
    for (int x = 3; x < size - 3; ++x) {
      const double l = Luminance(image, x, y);
      sum += l;
      ++pixels;
      for (const glm::ivec2 d : {glm::ivec2(1, 0), glm::ivec2(0, 1)}) {
        const double next = Luminance(image, x + d.x, y + d.y);
        const double prev = Luminance(image, x - d.x, y - d.y);
        second += std::abs(next + prev - 2.0 * l);
        jump = std::max(jump, std::abs(next - l));
        ++pairs;
      }
    }
  }
  Roughness r;
  r.mean = sum / pixels;
  r.second_difference = second / pairs / r.mean;
  r.max_jump = jump / r.mean;
  return r;
}

// The old reconstruction (each VPL through the roughness-0.3 lobe as a
// point, the 4 x 4 box) made 4 x 4 blocks: second difference 0.109 and
// largest jump 2.55 x the mean here; the box with the widened lobes 0.075
// and 0.83; the tent with the point lobes 0.024 and 0.60; both (now) 0.016
// and 0.33 (docs/RESULTS.md, avg glossy blocks). The bounds, 0.04 and
// 0.75, leave 2.3x above the measured figures for changes in VPL placement
// and fail on either half of the fix alone. The true image, the lit floor
// through a smooth lobe, changes slowly (a 1024-spp path-traced one is
// noise-dominated at this scale, so it is not the yardstick); its error
// against that reference stays at the old level (0.025 before, 0.018 now,
// bound 0.03) and the face's mean within 10 % of it: the widened lobes
// move light across the face, they neither add nor remove it.
TEST(AvgGlossyBlocks, FlatGlossyFaceShowsNoInterleaveBlocks) {
  const std::string id = LoadWallScene();
  ASSERT_FALSE(id.empty());
  const FloatImage avg = testing::RenderExr(testing::SharedEngine(), id, "avg", kSize, kSize,
                                            {{"area_samples", "16"}, {"shadow_res", "32"}});
  const FloatImage reference =
      testing::RenderExr(testing::SharedEngine(), id, "pathtrace", kSize, kSize, {{"spp", "1024"}});
  ASSERT_EQ(avg.width, int(kSize));
  ASSERT_EQ(reference.width, int(kSize));
  EXPECT_EQ(avg.non_finite(), 0u);
  // The lower half: the floor's reflection.
  const Roughness r = Measure(avg, kSize / 2, kSize), ref = Measure(reference, kSize / 2, kSize);
  const double error = testing::RelMse(avg, reference);
  testing::RecordMeasurement("second_difference", r.second_difference);
  testing::RecordMeasurement("max_jump", r.max_jump);
  testing::RecordMeasurement("mean", r.mean);
  testing::RecordMeasurement("reference_mean", ref.mean);
  testing::RecordMeasurement("relmse", error);
  EXPECT_LT(r.second_difference, 0.04);
  EXPECT_LT(r.max_jump, 0.75);
  EXPECT_LT(error, 0.03);
  EXPECT_NEAR(r.mean / ref.mean, 1.0, 0.1);
}

// The gold floor's VPLs light the grey wall through the lobe: each a spot
// on a few pixels of one subset, which the Lambertian receivers' 4 x 4 box
// showed as 4 x 4 blocks. The filter takes the tent for every receiver
// once a VPL is glossy. Measured on the wall (the upper half, lit mostly
// by the lamp, so the figures are small): mean second difference 0.0101 x
// the mean with the box, 0.0011 with the tent; the bound 0.004 fails the
// box by 2.5x and leaves the tent 3.6x.
TEST(AvgGlossyBlocks, GlossyVplsShowNoInterleaveBlocksOnALambertianWall) {
  const std::string id = LoadGoldFloorScene();
  ASSERT_FALSE(id.empty());
  const FloatImage avg = testing::RenderExr(testing::SharedEngine(), id, "avg", kSize, kSize,
                                            {{"area_samples", "16"}, {"shadow_res", "32"}});
  ASSERT_EQ(avg.width, int(kSize));
  EXPECT_EQ(avg.non_finite(), 0u);
  const Roughness r = Measure(avg, 0, kSize / 2);
  testing::RecordMeasurement("second_difference", r.second_difference);
  testing::RecordMeasurement("max_jump", r.max_jump);
  testing::RecordMeasurement("mean", r.mean);
  EXPECT_GT(r.mean, 0.0);
  EXPECT_LT(r.second_difference, 0.004);
}

}  // namespace avg_glossy_blocks_test
}  // namespace gistream
