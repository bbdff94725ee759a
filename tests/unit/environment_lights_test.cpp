// The environment map as median-cut directional lights
// (render/environment_lights.h) against closed forms: a uniform sky keeps
// its total L d(omega) = 4 pi L and gives every normal the irradiance pi L
// (the cosine quadrature of 32 lights within 10 %); a sun texel becomes one
// light in its direction with its L d(omega); a rotation turns the lights
// as the path tracer turns the map (shading/env_light.h).
#include <cmath>

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>

#include "render/environment_lights.h"
#include "scene/environment_cut.h"
#include "solvers/shading/env_light.h"
#include "support/measurement.h"

namespace gistream {
namespace environment_lights_test {

constexpr int kWidth = 64, kHeight = 32;
constexpr double kPi = glm::pi<double>();

Image Sky(float radiance) {
  Image image;
  image.width = kWidth;
  image.height = kHeight;
  image.is_float = true;
  image.srgb = false;
  image.pixelsf.assign(size_t(kWidth) * kHeight * 4, radiance);
  return image;
}

// The solid angle of texel row y.
double TexelAngle(int y) {
  return (2.0 * kPi / kWidth) * (kPi / kHeight) * std::sin(kPi * (y + 0.5) / kHeight);
}

TEST(EnvironmentLights, AUniformSkyKeepsItsEnergyAndLightsEveryNormalWithPiL) {
  const std::vector<EnvironmentRegionLight> lights =
      MedianCutEnvironment(Sky(1.0f), kEnvironmentLightCount);
  ASSERT_EQ(lights.size(), size_t(kEnvironmentLightCount));
  double total_texel_angle = 0.0;
  for (int y = 0; y < kHeight; ++y) total_texel_angle += TexelAngle(y) * kWidth;
  double total = 0.0;
  for (const EnvironmentRegionLight& l : lights) {
    EXPECT_NEAR(glm::length(l.to_sky), 1.0f, 1e-5f);
    total += double(l.irradiance.g);
  }
  // The texels' solid angles sum to 4 pi up to the rows' midpoint rule.
  EXPECT_NEAR(total, total_texel_angle, 1e-6 * total);  // float sums
  EXPECT_NEAR(total, 4.0 * kPi, 3e-3 * 4.0 * kPi);
  // Irradiance on a surface of normal n, over 400 normals spread over the
  // sphere: sum E_k max(0, n . d_k), pi L exactly for the sky itself. The
  // worst normal is 8.6 % off with 32 lights (16: 21 %, 64: 3.3 %): a
  // region straddling a surface's horizon counts wholly or not at all.
  double worst = 0.0, mean = 0.0;
  constexpr int kNormals = 400;
  for (int i = 0; i < kNormals; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / kNormals, r = std::sqrt(1.0 - z * z);
    const double phi = i * 2.399963;  // the golden angle
    const glm::vec3 n(float(r * std::cos(phi)), float(z), float(r * std::sin(phi)));
    double e = 0.0;
    for (const EnvironmentRegionLight& l : lights) {
      e += double(l.irradiance.g) * std::max(0.0, double(glm::dot(n, l.to_sky)));
    }
    worst = std::max(worst, std::abs(e / kPi - 1.0));
    mean += std::abs(e / kPi - 1.0) / kNormals;
  }
  testing::RecordMeasurement("worst_irradiance_error", worst);
  testing::RecordMeasurement("mean_irradiance_error", mean);
  EXPECT_LT(worst, 0.1);
  EXPECT_LT(mean, 0.04);
}

TEST(EnvironmentLights, ASunTexelBecomesOneLightInItsDirection) {
  Image image = Sky(0.0f);
  const int sx = 20, sy = 9;  // theta = pi 9.5 / 32, phi = 2 pi 20.5 / 64
  float* p = &image.pixelsf[(size_t(sy) * kWidth + sx) * 4];
  p[0] = p[1] = p[2] = 1000.0f;
  const std::vector<EnvironmentRegionLight> lights = MedianCutEnvironment(image, 16);
  ASSERT_EQ(lights.size(), 1u);  // the regions without light are dropped
  EXPECT_NEAR(double(lights[0].irradiance.r), 1000.0 * TexelAngle(sy),
              1e-4 * 1000.0 * TexelAngle(sy));
  // The path tracer finds the sun where the light points, at any rotation.
  const shading::EnvironmentLight env(image);
  for (const float rotation : {0.0f, 0.7f, -2.0f}) {
    const std::vector<EnvironmentRegionLight> placed =
        PlaceEnvironmentLights(lights, rotation, 2.0f);
    ASSERT_EQ(placed.size(), 1u);
    EXPECT_EQ(env.Radiance(placed[0].to_sky, rotation), glm::vec3(1000.0f)) << rotation;
    EXPECT_FLOAT_EQ(placed[0].irradiance.g, 2.0f * lights[0].irradiance.g);
  }
}

TEST(EnvironmentLights, NoneForABlackOrEmptyMap) {
  EXPECT_TRUE(MedianCutEnvironment(Sky(0.0f), 16).empty());
  EXPECT_TRUE(MedianCutEnvironment(Image{}, 16).empty());
  EXPECT_TRUE(MedianCutEnvironment(Sky(1.0f), 0).empty());
  // Negative or non-finite texels carry no light.
  Image broken = Sky(1.0f);
  broken.pixelsf[0] = std::nanf("");
  broken.pixelsf[5] = -1.0f;
  for (const EnvironmentRegionLight& l : MedianCutEnvironment(broken, 16)) {
    EXPECT_TRUE(std::isfinite(l.irradiance.r + l.irradiance.g + l.irradiance.b));
    EXPECT_GE(std::min({l.irradiance.r, l.irradiance.g, l.irradiance.b}), 0.0f);
  }
}

}  // namespace environment_lights_test
}  // namespace gistream
