// The G-buffer drawn from one indirect draw list (render/view_passes.h,
// issue 30): every primitive shades with its own material (the record's,
// not a uniform set per draw), and the list kept between frames belongs to
// the scene state it was made from: views of two scenes rendered in turn
// each show their own scene.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/gltf_builder.h"
#include "support/render_helpers.h"

namespace gistream {
namespace gbuffer_list_test {

using testing::FloatImage;
using testing::GltfBuilder;

constexpr uint32_t kSize = 32;
constexpr int kGrid = 4;
constexpr float kYfov = 0.7f;
constexpr float kDistance = 3.0f;

// Quad (i, j)'s centre, a 4 x 4 grid in z = 0 with 0.5 m spacing.
glm::vec2 Centre(int i, int j) { return {-0.75f + 0.5f * float(i), -0.75f + 0.5f * float(j)}; }
// Its emitted colour: every quad a different one, no light in the scene.
glm::vec3 Emission(int i, int j) {
  return {0.1f + 0.25f * float(i), 0.1f + 0.25f * float(j), 0.9f - 0.05f * float(i + kGrid * j)};
}

std::string LoadGrid() {
  GltfBuilder b;
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const glm::vec3 e = Emission(i, j);
      const int m = b.AddMaterial("m", {0, 0, 0}, {e.x, e.y, e.z});
      const glm::vec2 c = Centre(i, j);
      b.AddQuad("q", {c.x, c.y, 0}, {0.2f, 0, 0}, {0, 0.2f, 0}, m);
    }
  }
  b.AddCamera("camera", {0, 0, kDistance}, {0, 0, -1}, {0, 1, 0}, kYfov);
  auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(b.ToJson()));
  EXPECT_TRUE(info.ok()) << info.status();
  return info.ok() ? info->id : "";
}

// The pixel a point of z = 0 lands on (rows top first).
glm::ivec2 Pixel(glm::vec2 p) {
  const float half = kDistance * std::tan(0.5f * kYfov);
  return {int((0.5f + 0.5f * p.x / half) * float(kSize)),
          int((0.5f - 0.5f * p.y / half) * float(kSize))};
}

TEST(GBufferList, EachPrimitiveShowsItsOwnMaterial) {
  const std::string grid = LoadGrid();
  ASSERT_FALSE(grid.empty());
  const FloatImage image =
      testing::RenderExr(testing::SharedEngine(), grid, "direct", kSize, kSize);
  ASSERT_EQ(image.width, int(kSize));
  // Each quad's centre shows its emission (radiance = emissive x strength 1,
  // nothing else lights it), to 1 % per channel.
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const glm::ivec2 px = Pixel(Centre(i, j));
      const glm::vec3 got = image.at(px.x, px.y), want = Emission(i, j);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(got[c], want[c], 0.01f * want[c]) << "quad (" << i << ", " << j << ") channel "
                                                      << c << " at pixel " << px.x << ", " << px.y;
      }
    }
  }
  EXPECT_TRUE(testing::SharedEngine().UnloadScene(grid).ok());
}

TEST(GBufferList, ViewsOfTwoScenesInTurnEachShowTheirOwnScene) {
  testing::BundledCopy cornell("cornell_box.gltf");
  const std::string grid = LoadGrid();
  ASSERT_FALSE(grid.empty());
  Engine& engine = testing::SharedEngine();
  const FloatImage first = testing::RenderExr(engine, cornell.id(), "direct", kSize, kSize);
  const FloatImage other = testing::RenderExr(engine, grid, "direct", kSize, kSize);
  const FloatImage again = testing::RenderExr(engine, cornell.id(), "direct", kSize, kSize);
  // The same scene state gives the same picture (to float rounding)...
  testing::ExpectSameImage(again, first, 1e-5f);
  // ...and the other scene's list was not drawn in its place: the grid's
  // picture is far from the box's (relMSE of order 1 where they differ).
  EXPECT_GT(testing::RelMse(other, first), 0.1);
  EXPECT_TRUE(engine.UnloadScene(grid).ok());
}

}  // namespace gbuffer_list_test
}  // namespace gistream
