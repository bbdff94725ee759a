// The solvers that light surfaces through shadow-mapped lights (`direct`,
// `avg`, `sh_probes`) light the environment map as median-cut directional
// lights (render/environment_lights.h); before, a file loaded with an
// environment rendered black in them. A plane of albedo 0.5 under a
// uniform environment (radiance 1, intensity 2) receives E = 2 pi, so
// L = rho / pi E = 2 rho = 1: within 5 % (the 32 lights' quadrature
// gives the up normal 1.033 of it, the same in each solver; nothing else
// is in the scene, so there is no interreflection). An environment update is a light change: at
// intensity 1 the plane halves (1e-3).
#include <string>

#include <gtest/gtest.h>

#include "encode/encode.h"
#include "support/gltf_builder.h"
#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace {

constexpr float kAlbedo = 0.5f;

class EnvironmentLit : public ::testing::TestWithParam<std::string> {
 protected:
  static void SetUpTestSuite() {
    testing::GltfBuilder b;
    const int mat = b.AddMaterial("plane", {kAlbedo, kAlbedo, kAlbedo});
    b.AddQuad("plane", {0, 0, 0}, {0, 0, 100}, {100, 0, 0}, mat);
    b.AddCamera("camera", {0.0f, 1.0f, 0.0f}, {0, -1, 0}, {0, 0, -1}, 1.0f);
    std::vector<float> rgba;
    for (int i = 0; i < 32 * 16; ++i) rgba.insert(rgba.end(), {1.0f, 1.0f, 1.0f, 1.0f});
    auto exr = EncodeExr(rgba, 32, 16);
    ASSERT_TRUE(exr.ok()) << exr.status();
    SceneSource source = testing::SceneFromBytes(b.ToJson());
    source.environment_bytes = *exr;
    source.environment_intensity = 2.0f;
    auto info = testing::SharedEngine().LoadScene(source);
    ASSERT_TRUE(info.ok()) << info.status();
    scene_ = new std::string(info->id);
  }
  static void TearDownTestSuite() {
    if (scene_) (void)testing::SharedEngine().UnloadScene(*scene_);
    delete scene_;
    scene_ = nullptr;
  }
  static std::string* scene_;
};
std::string* EnvironmentLit::scene_ = nullptr;

TEST_P(EnvironmentLit, APlaneUnderAUniformSkyReflectsRhoOverPiTimesE) {
  const std::string& solver = GetParam();
  EncodedFrame frame;
  const testing::FloatImage lit = testing::RenderRequestExr(
      testing::SolverRequest(*scene_, solver, {{"area_samples", "4"}}, 16), &frame);
  ASSERT_EQ(lit.width, 16);
  EXPECT_EQ(lit.non_finite(), 0u);
  const double l = testing::ImageMean(lit).g;
  testing::RecordMeasurement("plane_radiance", l);
  EXPECT_NEAR(l, 2.0 * kAlbedo, 0.05 * 2.0 * kAlbedo) << solver;

  EnvironmentUpdate dim;
  dim.intensity = 1.0f;
  const testing::FloatImage dimmed = testing::RenderRequestExr(
      testing::SolverRequest(*scene_, solver, {{"area_samples", "4"}}, 16, {{1, dim}}));
  EXPECT_NEAR(testing::ImageMean(dimmed).g / l, 0.5, 1e-3) << solver;
  EnvironmentUpdate back;
  back.intensity = 2.0f;
  testing::RenderRequestExr(
      testing::SolverRequest(*scene_, solver, {{"area_samples", "4"}}, 16, {{2, back}}));
}

INSTANTIATE_TEST_SUITE_P(Rasterizing, EnvironmentLit,
                         ::testing::Values("direct", "avg", "sh_probes"),
                         [](const auto& p) { return p.param; });

}  // namespace
}  // namespace gistream
