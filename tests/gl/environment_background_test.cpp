// Where no geometry covers a pixel, every solver shows the environment's
// radiance along the pixel's ray (render/view_passes.h, shaders/render/
// sky.frag.glsl), as pathtrace's camera rays do; before, the rasterizing
// solvers drew black there, so a sample model viewed under an environment
// sat on black and every eval against pathtrace counted the sky as error.
// Closed form: a map whose texels are all different (R by column, G by
// row) seen from a camera at the origin looking down -Z: each pixel centre
// shows the texel its ray lands in (the equirectangular mapping of
// solvers/shading/env_light.cpp), times the intensity, and an environment
// update (rotation, intensity) moves and scales it.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/gltf_builder.h"
#include "support/registered_solvers.h"
#include "support/render_helpers.h"

namespace gistream {
namespace environment_background_test {

constexpr int kMapWidth = 32, kMapHeight = 16;
constexpr int kSize = 16;
constexpr float kYfov = 1.0f;

glm::vec3 Texel(int x, int y) {
  return {(float(x) + 0.5f) / kMapWidth, (float(y) + 0.5f) / kMapHeight, 0.25f};
}

// What pixel (px, py) (rows top first) shows: its centre's ray from the
// camera (identity rotation, looking down -Z) located in the map as
// EnvironmentLight::Locate does.
glm::vec3 Expected(int px, int py, float rotation, float intensity) {
  const float t = std::tan(0.5f * kYfov);
  const float nx = (float(px) + 0.5f) / kSize * 2.0f - 1.0f;
  const float ny = (float(kSize - py) - 0.5f) / kSize * 2.0f - 1.0f;
  const glm::vec3 dir = glm::normalize(glm::vec3(nx * t, ny * t, -1.0f));
  float u = (std::atan2(dir.x, -dir.z) - rotation) / (2.0f * float(M_PI));
  u -= std::floor(u);
  const float theta = std::acos(std::clamp(dir.y, -1.0f, 1.0f));
  const int x = std::clamp(int(u * kMapWidth), 0, kMapWidth - 1);
  const int y = std::clamp(int(theta / float(M_PI) * kMapHeight), 0, kMapHeight - 1);
  return Texel(x, y) * intensity;
}

class EnvironmentBackground : public ::testing::TestWithParam<std::string> {
 protected:
  static void SetUpTestSuite() {
    testing::GltfBuilder b;
    // Behind the camera: the whole view is background.
    b.AddQuad("floor", {0, -1, 5}, {0, 0, 1}, {1, 0, 0}, b.AddMaterial("grey", {0.5f, 0.5f, 0.5f}));
    b.AddCamera("camera", {0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kYfov);
    SceneSource source = testing::SceneFromBytes(b.ToJson());
    source.environment_bytes = testing::EnvironmentExr(kMapWidth, kMapHeight, Texel);
    source.environment_intensity = 2.0f;
    scene_ = std::make_unique<testing::TestScene>(std::move(source));
  }
  static void TearDownTestSuite() { scene_.reset(); }

  // Every pixel within float rounding of its texel, but for at most two
  // whose centre lies on a texel boundary (within a texel step there).
  static void ExpectSky(const testing::FloatImage& image, float rotation, float intensity) {
    ASSERT_EQ(image.width, kSize);
    int off = 0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const glm::vec3 got = image.at(x, y), want = Expected(x, y, rotation, intensity);
        const float diff = glm::length(got - want);
        if (diff <= 2e-3f * glm::length(want)) continue;
        ++off;
        EXPECT_LE(diff, 1.5f * intensity / kMapHeight) << x << "," << y;
      }
    }
    EXPECT_LE(off, 2);
  }
  static std::unique_ptr<testing::TestScene> scene_;
};
std::unique_ptr<testing::TestScene> EnvironmentBackground::scene_;

TEST_P(EnvironmentBackground, ShowsTheMapAlongEachPixelsRay) {
  const std::string& solver = GetParam();
  // The scene's light is the map's 32 median-cut lights: one area sample
  // would be spent on no emitter.
  const std::map<std::string, std::string> params;
  // Each render sets the environment it expects (the suite shares one
  // scene, and the solvers run in any order).
  EnvironmentUpdate as_loaded;
  as_loaded.rotation = 0.0f;
  as_loaded.intensity = 2.0f;
  const testing::FloatImage sky = testing::RenderRequestExr(
      testing::SolverRequest(scene_->id(), solver, params, kSize, {{1, as_loaded}}));
  if (solver == "pathtrace") {
    // Its camera rays sample the whole pixel (a box filter): the same
    // map, each pixel the mean of its footprint. The image means agree.
    double got = 0.0, want = 0.0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        got += sky.at(x, y).r + sky.at(x, y).g;
        want += Expected(x, y, 0.0f, 2.0f).r + Expected(x, y, 0.0f, 2.0f).g;
      }
    }
    EXPECT_NEAR(got / want, 1.0, 0.02);
    return;
  }
  ExpectSky(sky, 0.0f, 2.0f);
  EnvironmentUpdate turn;
  turn.rotation = 0.7f;
  turn.intensity = 1.0f;
  ExpectSky(testing::RenderRequestExr(
                testing::SolverRequest(scene_->id(), solver, params, kSize, {{2, turn}})),
            0.7f, 1.0f);
}

INSTANTIATE_TEST_SUITE_P(EverySolver, EnvironmentBackground,
                         ::testing::ValuesIn(testing::RegisteredSolverNames()),
                         [](const auto& p) { return p.param; });

}  // namespace environment_background_test
}  // namespace gistream
