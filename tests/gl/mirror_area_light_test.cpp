// A near-mirror floor under an area lamp (issue 29): the direct light's
// area samples are the lamp's only directions, so a GGX lobe narrower
// than their spacing showed the lamp's reflection as one spot per sample
// on a dark floor. Each sample's lobe is now widened to the solid angle
// the sample stands for (shaders/render/direct_light.glsl,
// BrdfEvalSource), which every rasterizing solver's direct light shares.
//
// Closed form: a 50 cm square lamp (L = 1, facing down) 1 m over a metal
// floor (base colour 0.9, roughness 0.05); a camera 80 cm over the floor
// looks straight down (yfov 0.5 rad) at the lamp's mirror image. Where
// the mirror direction meets the lamp well inside its outline the floor
// reflects F L, F the Schlick Fresnel of F0 = 0.9 at normal incidence
// (0.9 within 1e-4 over the view) times the lobe's directional albedo
// (GGX single scattering at roughness 0.05: 1 - 2e-3), so 0.9 within 1 %.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "support/gltf_builder.h"
#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace mirror_area_light_test {

using testing::GltfBuilder;

constexpr uint32_t kSize = 48;
constexpr double kExpected = 0.9;
// The lamp's image is 26 px wide (tan(7.9 deg) / tan(14.3 deg) x 48):
// the central 15 x 15 pixels see its interior, 6 px from its outline.
constexpr int kWindow = 7;

class MirrorAreaLight : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    GltfBuilder b;
    const int lamp = b.AddMaterial("lamp", {0, 0, 0}, {1, 1, 1});
    const int metal = b.AddMaterial("metal", {0.9f, 0.9f, 0.9f});
    b.SetMetallicRoughness(metal, 1.0f, 0.05f);
    b.AddQuad("lamp", {0, 1, 0}, {0.25f, 0, 0}, {0, 0, 0.25f}, lamp, 1);  // faces -Y
    b.AddQuad("floor", {0, 0, 0}, {0, 0, 2}, {2, 0, 0}, metal, 1);        // faces +Y
    b.AddCamera("camera", {0, 0.8f, 0}, {0, -1, 0}, {0, 0, 1}, 0.5f);
    scene_ = std::make_unique<testing::TestScene>(testing::SceneFromBytes(b.ToJson()));
  }
  static void TearDownTestSuite() { scene_.reset(); }

  struct Window {
    double mean = 0.0;
    double cv = 0.0;  // standard deviation / mean over the window's pixels
  };
  // Green radiance over the central window of `solver`'s picture.
  static Window Reflection(const std::string& solver,
                           const std::map<std::string, std::string>& params) {
    const testing::FloatImage image =
        testing::RenderExr(testing::SharedEngine(), scene_->id(), solver, kSize, kSize, params, {});
    EXPECT_EQ(image.width, int(kSize)) << solver;
    EXPECT_EQ(image.non_finite(), 0u) << solver;
    if (image.width != int(kSize)) return {};
    double sum = 0.0, sum2 = 0.0;
    int n = 0;
    for (int y = int(kSize) / 2 - kWindow; y <= int(kSize) / 2 + kWindow; ++y) {
      for (int x = int(kSize) / 2 - kWindow; x <= int(kSize) / 2 + kWindow; ++x) {
        const double g = image.at(x, y).g;
        sum += g;
        sum2 += g * g;
        ++n;
      }
    }
    Window w;
    w.mean = sum / n;
    w.cv = w.mean > 0.0 ? std::sqrt(std::max(0.0, sum2 / n - w.mean * w.mean)) / w.mean : 0.0;
    return w;
  }

  static std::unique_ptr<testing::TestScene> scene_;
};
std::unique_ptr<testing::TestScene> MirrorAreaLight::scene_;

// The reference agrees with the closed form (2 %: its noise at 64 spp
// where light sampling and BSDF sampling share the lamp).
TEST_F(MirrorAreaLight, PathtraceReflectsFL) {
  const Window w = Reflection("pathtrace", {{"spp", "64"}});
  testing::RecordMeasurement("pathtrace_mean", w.mean);
  testing::RecordMeasurement("pathtrace_cv", w.cv);
  EXPECT_NEAR(w.mean, kExpected, 0.02 * kExpected);
}

// `direct` at its defaults (32 area samples, one per 7.8e-3 m^2 of lamp):
// the reflection is one even image of the lamp, F L within 10 % on average
// (measured 0.845, 6 % low: the widened lobes' tails reach past the lamp)
// and its pixels within 15 % of their mean (coefficient of variation,
// measured 0.12). Before the widening the window showed the samples as
// spots: coefficient of variation 4.1 (most pixels black, a few at many
// times L; mean 1.07).
TEST_F(MirrorAreaLight, DirectShowsTheLampNotItsSamples) {
  const Window w = Reflection("direct", {});
  testing::RecordMeasurement("direct_mean", w.mean);
  testing::RecordMeasurement("direct_cv", w.cv);
  EXPECT_NEAR(w.mean, kExpected, 0.1 * kExpected);
  EXPECT_LT(w.cv, 0.15);
}

}  // namespace mirror_area_light_test
}  // namespace gistream
