// The reference path tracer on a glossy white furnace, without GL: the
// bundled furnace (a closed cube emitting L_e = 1 everywhere inside) made
// of white metal (baseColor 1, metallic 1: F0 = 1) at several roughnesses.
//
// One bounce (max_depth 1): emission plus light sampling and BRDF sampling
// of the next vertex's emission, combined by MIS. Every direction sees
// L_e = 1, so the exact answer is 1 + albedo(wo), the BRDF's directional
// albedo at the first hit, integrated numerically from ggx.h here. This
// checks the BRDF's sampling, pdf and MIS weights together.
//
// All bounces: the radiance stays within [1 / (1 - min albedo), 1 /
// (1 - max albedo)] (if L <= M everywhere, L <= 1 + max albedo M): energy
// bounded by the BRDF's albedo, which is itself <= 1 (ggx_test.cpp).
//
// Both with N paths along one direction from one point: |mean - exact| <=
// 4 standard errors (p < 1e-4 of a false alarm).
#include <cmath>
#include <memory>
#include <vector>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "support/measurement.h"

#include "scene/gltf/gltf_import.h"
#include "scene/state/scene_state.h"
#include "solvers/shading/ggx.h"
#include "solvers/pathtrace/integrator.h"
#include "solvers/shading/sampling.h"
#include "solvers/pathtrace/scene_bvh.h"
#include "util/parallel_for.h"

namespace gistream {
namespace pathtrace_glossy_furnace_test {

constexpr double kPi = 3.14159265358979323846;
const glm::vec3 kOrigin(0.1f, -0.2f, 0.05f);  // inside the 2 m cube

// Directional albedo of white metal at view cosine cos_o (midpoint rule).
double MetalAlbedo(float roughness, double cos_o) {
  const shading::Brdf brdf{glm::vec3(1.0f), 1.0f, roughness};
  const glm::vec3 wo(float(std::sqrt(1.0 - cos_o * cos_o)), 0.0f, float(cos_o));
  const int n = 600;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double c = (i + 0.5) / n, s = std::sqrt(1.0 - c * c);
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = (j + 0.5) * kPi / n;
      const glm::vec3 wi(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c));
      sum += shading::Eval(brdf, wo, wi).x * c;
    }
  }
  return sum * (1.0 / n) * (kPi / n);
}

struct Estimate {
  double mean = 0.0, standard_error = 0.0;
};

Estimate Trace(float roughness, const glm::vec3& dir, int paths, int max_depth) {
  auto scene = ImportSceneByName(std::string(GISTREAM_SOURCE_DIR "/scenes"), "furnace", {});
  EXPECT_TRUE(scene.ok()) << scene.status();
  if (!scene.ok()) return {};
  Scene glossy = *std::move(scene);
  glossy.materials[0].base_color_factor = glm::vec4(1.0f);
  glossy.materials[0].metallic_factor = 1.0f;
  glossy.materials[0].roughness_factor = roughness;
  SceneState state(std::make_shared<const Scene>(std::move(glossy)));
  auto bvh = pathtrace::SceneBvh::Build(state);
  EXPECT_TRUE(bvh.ok()) << bvh.status();
  if (!bvh.ok()) return {};
  pathtrace::IntegratorSettings settings;
  settings.max_depth = max_depth;
  const pathtrace::Integrator integrator(state, **bvh, nullptr, settings);
  std::vector<double> value(size_t(paths), 0.0);
  ParallelFor(size_t(paths), 64, [&](size_t i) {
    shading::Rng rng(0x91055, uint64_t(i));
    pathtrace::PathStats stats;
    value[i] = double(integrator.Li(kOrigin, dir, rng, stats).g);
  });
  double sum = 0.0, sum2 = 0.0;
  for (double v : value) {
    EXPECT_TRUE(std::isfinite(v));
    sum += v;
    sum2 += v * v;
  }
  const double n = double(paths);
  Estimate e;
  e.mean = sum / n;
  e.standard_error = std::sqrt(std::max(0.0, (sum2 - n * e.mean * e.mean) / (n - 1.0)) / n);
  return e;
}

// A unit direction from kOrigin that meets the floor (y = -1) at view
// cosine cos_o.
glm::vec3 TowardsFloor(double cos_o) {
  return glm::vec3(float(std::sqrt(1.0 - cos_o * cos_o)), float(-cos_o), 0.0f);
}

TEST(PathtraceGlossyFurnace, OneBounceIsOnePlusTheAlbedo) {
  for (float roughness : {1.0f, 0.6f, 0.3f}) {
    // Both directions meet the floor (cos 0.75: at x = 0.81 < 1).
    for (double cos_o : {1.0, 0.75}) {
      const double exact = 1.0 + MetalAlbedo(roughness, cos_o);
      const Estimate e = Trace(roughness, TowardsFloor(cos_o), 16384, 1);
      testing::RecordMeasurement(absl::StrCat("mean_roughness_", roughness, "_cos_", cos_o),
                                 e.mean);
      EXPECT_NEAR(e.mean, exact, 4.0 * e.standard_error + 1e-3)
          << "roughness " << roughness << " cos_o " << cos_o;
    }
  }
}

TEST(PathtraceGlossyFurnace, AllBouncesBoundedByTheAlbedo) {
  for (float roughness : {1.0f, 0.5f}) {
    double lo = 1.0, hi = 0.0;
    for (int i = 0; i < 20; ++i) {
      const double a = MetalAlbedo(roughness, (i + 0.5) / 20.0);
      lo = std::min(lo, a);
      hi = std::max(hi, a);
    }
    // The grid of 20 cosines can miss the extremes by a little: 1 % slack.
    lo *= 0.99;
    hi = std::min(1.0, hi * 1.01);
    ASSERT_LT(hi, 1.0);
    const Estimate e = Trace(roughness, TowardsFloor(0.8), 8192, 0);
    testing::RecordMeasurement(absl::StrCat("mean_roughness_", roughness), e.mean);
    EXPECT_GE(e.mean + 4.0 * e.standard_error, 1.0 / (1.0 - lo)) << "roughness " << roughness;
    EXPECT_LE(e.mean - 4.0 * e.standard_error, 1.0 / (1.0 - hi)) << "roughness " << roughness;
  }
}

}  // namespace pathtrace_glossy_furnace_test
}  // namespace gistream
