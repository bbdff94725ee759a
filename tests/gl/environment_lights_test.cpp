// The solvers that light surfaces through shadow-mapped lights (`direct`,
// `avg`, `sh_probes`, `antiradiance`) light the environment map as
// median-cut directional lights (render/environment_lights.h); before, a
// file loaded with an environment rendered black in them. A plane of albedo 0.5 under a
// uniform environment (radiance 1, intensity 2) receives E = 2 pi, so
// L = rho / pi E = 2 rho = 1: within 5 % (the 32 lights' quadrature
// gives the up normal 1.033 of it, the same in each solver; nothing else
// is in the scene, so there is no interreflection). An environment update is a light change: at
// intensity 1 the plane halves (1e-3).
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "support/gltf_builder.h"
#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace environment_lights_test {

constexpr float kAlbedo = 0.5f;

class EnvironmentLit : public ::testing::TestWithParam<std::string> {
 protected:
  static void SetUpTestSuite() {
    testing::GltfBuilder b;
    const int mat = b.AddMaterial("plane", {kAlbedo, kAlbedo, kAlbedo});
    b.AddQuad("plane", {0, 0, 0}, {0, 0, 100}, {100, 0, 0}, mat);
    b.AddCamera("camera", {0.0f, 1.0f, 0.0f}, {0, -1, 0}, {0, 0, -1}, 1.0f);
    SceneSource source = testing::SceneFromBytes(b.ToJson());
    source.environment_bytes = testing::UniformEnvironmentExr(1.0f, 32, 16);
    source.environment_intensity = 2.0f;
    scene_ = std::make_unique<testing::TestScene>(std::move(source));
  }
  static void TearDownTestSuite() { scene_.reset(); }
  static std::unique_ptr<testing::TestScene> scene_;
};
std::unique_ptr<testing::TestScene> EnvironmentLit::scene_;

TEST_P(EnvironmentLit, APlaneUnderAUniformSkyReflectsRhoOverPiTimesE) {
  const std::string& solver = GetParam();
  EncodedFrame frame;
  const testing::FloatImage lit = testing::RenderRequestExr(
      testing::SolverRequest(scene_->id(), solver, {{"area_samples", "4"}}, 16), &frame);
  ASSERT_EQ(lit.width, 16);
  EXPECT_EQ(lit.non_finite(), 0u);
  const double l = testing::ImageMean(lit).g;
  testing::RecordMeasurement("plane_radiance", l);
  EXPECT_NEAR(l, 2.0 * kAlbedo, 0.05 * 2.0 * kAlbedo) << solver;

  EnvironmentUpdate dim;
  dim.intensity = 1.0f;
  const testing::FloatImage dimmed = testing::RenderRequestExr(
      testing::SolverRequest(scene_->id(), solver, {{"area_samples", "4"}}, 16, {{1, dim}}));
  EXPECT_NEAR(testing::ImageMean(dimmed).g / l, 0.5, 1e-3) << solver;
  EnvironmentUpdate back;
  back.intensity = 2.0f;
  testing::RenderRequestExr(
      testing::SolverRequest(scene_->id(), solver, {{"area_samples", "4"}}, 16, {{2, back}}));
}

INSTANTIATE_TEST_SUITE_P(Rasterizing, EnvironmentLit,
                         ::testing::Values("direct", "avg", "sh_probes", "antiradiance"),
                         [](const auto& p) { return p.param; });

}  // namespace environment_lights_test
}  // namespace gistream
