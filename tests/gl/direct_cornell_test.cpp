// The Cornell box under the `direct` solver at 128x128 (llvmpipe-sized):
// image regions must show what direct light alone produces.
#include <gtest/gtest.h>

#include "scene/gltf/gltf_import.h"
#include "support/render_helpers.h"

namespace gistream {
namespace direct_cornell_test {

using testing::FloatImage;

class DirectCornellTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto info = testing::SharedEngine().LoadScene(testing::SceneByName("cornell_box"));
    ASSERT_TRUE(info.ok()) << info.status();
    scene_id_ = info->id;
    auto scene = ImportSceneByName(std::string(GISTREAM_SOURCE_DIR "/scenes"), "cornell_box", {});
    ASSERT_TRUE(scene.ok()) << scene.status();
    state_ = std::make_unique<SceneState>(std::make_shared<const Scene>(*std::move(scene)));
    camera_ = DefaultCamera(*state_, kSize, kSize);
    image_ = testing::RenderExr(testing::SharedEngine(), scene_id_, "direct", kSize, kSize);
  }
  static glm::vec3 At(const glm::vec3& world) {
    const glm::ivec2 p = testing::Project(camera_, world);
    EXPECT_TRUE(p.x >= 1 && p.y >= 1 && p.x < int(kSize) - 1 && p.y < int(kSize) - 1)
        << "point projects outside the image: " << p.x << "," << p.y;
    return image_.mean(p.x, p.y, 1);
  }

  static constexpr uint32_t kSize = 128;
  static inline std::string scene_id_;
  static inline std::unique_ptr<SceneState> state_;
  static inline ViewCamera camera_;
  static inline FloatImage image_;
};

TEST_F(DirectCornellTest, OutputIsFinite) {
  ASSERT_EQ(image_.width, int(kSize));
  EXPECT_EQ(image_.non_finite(), 0u);
}

TEST_F(DirectCornellTest, LightRegionIsBrightest) {
  // The emitter's radiance (17 nits in green) exceeds any lit surface,
  // whose outgoing radiance is albedo/pi * E.
  const glm::vec3 light = At({0.278f, 0.548f, 0.2795f});
  float brightest_elsewhere = 0.0f;
  const glm::ivec2 lp = testing::Project(camera_, {0.278f, 0.548f, 0.2795f});
  for (int y = 0; y < image_.height; ++y) {
    for (int x = 0; x < image_.width; ++x) {
      if (std::abs(x - lp.x) < 12 && std::abs(y - lp.y) < 6) continue;  // the quad itself
      brightest_elsewhere = std::max(brightest_elsewhere, image_.at(x, y).g);
    }
  }
  EXPECT_GT(light.g, 10.0f);
  EXPECT_GT(light.g, 2.0f * brightest_elsewhere);
}

TEST_F(DirectCornellTest, LeftWallRedRightWallGreen) {
  const glm::vec3 left = At({0.555f, 0.25f, 0.35f});
  const glm::vec3 right = At({0.001f, 0.25f, 0.35f});
  EXPECT_GT(left.r, 3.0f * left.g) << "left wall should be red";
  EXPECT_GT(left.r, 3.0f * left.b);
  EXPECT_GT(right.g, 1.5f * right.r) << "right wall should be green";
  EXPECT_GT(right.g, 1.5f * right.b);
  EXPECT_GT(left.r, 0.01f);
  EXPECT_GT(right.g, 0.01f);
}

TEST_F(DirectCornellTest, FloorBesideTallBlockIsShadowed) {
  // (0.50, 0, 0.35): the segment to the light centre passes through the
  // tall block (footprint corners (423,247) (265,296) (314,456) (472,406) mm,
  // height 330 mm); (0.45, 0, 0.12) in front of it sees the light.
  const glm::vec3 shadowed = At({0.50f, 0.0f, 0.35f});
  const glm::vec3 open = At({0.45f, 0.0f, 0.12f});
  EXPECT_GT(open.r, 0.05f);
  EXPECT_LT(shadowed.r, 0.5f * open.r);
}

}  // namespace direct_cornell_test
}  // namespace gistream
