// A dimmer on every GI solver: when every light of the scene is scaled by
// one factor (here the Cornell box's only emitter, strength 10 -> 20), the
// image scales by it exactly (light transport is linear in the emission),
// the solver runs none of its view-independent GI stages and redraws no
// shadow map, and the result equals a fresh solve at the new strength.
#include <gtest/gtest.h>

#include "support/render_helpers.h"
#include "support/registered_solvers.h"

namespace gistream {
namespace dimmer_test {

using testing::BundledCopy;
using testing::FloatImage;
using testing::FrameStage;

struct Case {
  std::string solver;
  std::map<std::string, std::string> params;
  std::vector<std::string> skipped;  // GI stages a dimmer must not run
  std::string zero_stat = "";        // a stat that must be 0 after the dimmer
};

class Dimmer : public ::testing::TestWithParam<Case> {};

Update Emission(float strength, uint64_t seq) {
  MaterialUpdate m;
  m.material = 3;  // cornell_box's "light" material
  m.emissive_strength = strength;
  return {seq, m};
}

FloatImage Render(const std::string& scene, const Case& c, std::vector<Update> updates,
                  EncodedFrame* frame) {
  return testing::RenderRequestExr(
      testing::SolverRequest(scene, c.solver, c.params, 32, std::move(updates)), frame);
}

TEST_P(Dimmer, ScalesTheImageWithoutASolve) {
  const Case& c = GetParam();
  const BundledCopy scene("cornell_box.gltf"), fresh_scene("cornell_box.gltf");
  EncodedFrame first_frame, dimmed_frame, fresh_frame;
  const FloatImage first = Render(scene.id(), c, {Emission(10.0f, 1)}, &first_frame);
  const FloatImage dimmed = Render(scene.id(), c, {Emission(20.0f, 2)}, &dimmed_frame);
  const FloatImage fresh = Render(fresh_scene.id(), c, {Emission(20.0f, 1)}, &fresh_frame);
  for (const std::string& stage : c.skipped) {
    const StageTiming* t = FrameStage(dimmed_frame, stage);
    ASSERT_NE(t, nullptr) << stage;
    EXPECT_TRUE(t->skipped) << c.solver << ": " << stage << " ran for a dimmer";
    const StageTiming* ran = FrameStage(first_frame, stage);
    ASSERT_NE(ran, nullptr) << stage;
    EXPECT_FALSE(ran->skipped) << c.solver << ": " << stage << " did not run for the first solve";
  }
  if (!c.zero_stat.empty()) {
    EXPECT_GT(testing::FrameStat(first_frame, c.zero_stat), 0.0) << c.zero_stat;
    EXPECT_EQ(testing::FrameStat(dimmed_frame, c.zero_stat), 0.0) << c.zero_stat;
  }
  ASSERT_EQ(first.rgba.size(), dimmed.rgba.size());
  ASSERT_EQ(fresh.rgba.size(), dimmed.rgba.size());
  // Linear transport: exactly twice (float rounding of the products only,
  // 1e-4 relative); and what a fresh solve at strength 20 gives, to 1e-3
  // relative (the fresh solve's sums run in another order, and sh_probes
  // and implicit_visibility stop their bounces at a relative tolerance
  // that is the same at both strengths).
  double lit = 0.0;
  for (size_t i = 0; i < first.rgba.size(); i += 4) {
    for (size_t ch = 0; ch < 3; ++ch) {
      const float a = first.rgba[i + ch], b = dimmed.rgba[i + ch], f = fresh.rgba[i + ch];
      ASSERT_NEAR(b, 2.0f * a, 1e-4f * std::max(1.0f, 2.0f * a)) << c.solver << " pixel " << i / 4;
      ASSERT_NEAR(b, f, 1e-3f * std::max(1.0f, f)) << c.solver << " pixel " << i / 4;
      lit += a;
    }
  }
  EXPECT_GT(lit, 0.0);
}

const std::vector<Case> kDimmerCases = {
    Case{"sh_probes",
         {{"grid", "4"}, {"face_size", "8"}, {"area_samples", "8"}, {"shadow_res", "64"}},
         {"rasterize_cubemaps", "render_cubemaps", "sh_project"}},
    Case{"avg",
         {{"vpls", "64"},
          {"grid", "16"},
          {"shadow_res", "16"},
          {"area_samples", "8"},
          {"direct_shadow_res", "64"}},
         {"voxelize"},
         "vpl_maps_redrawn"},
    Case{"implicit_visibility",
         {{"bins_per_face", "4"}, {"area_samples", "8"}, {"shadow_res", "64"}},
         {"create_links", "illumination"}},
    Case{"antiradiance",
         {{"bins", "32"}, {"iterations", "2"}, {"area_samples", "8"}, {"shadow_res", "64"}},
         {"link", "global_pass", "push_pull"}}};

INSTANTIATE_TEST_SUITE_P(GiSolvers, Dimmer, ::testing::ValuesIn(kDimmerCases),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.solver; });

TEST(Dimmer, CoversEveryRegisteredSolver) {
  std::set<std::string> run;
  for (const Case& c : kDimmerCases) run.insert(c.solver);
  testing::ExpectCoversEveryRegisteredSolver(
      run, {{"direct", "no GI stage for a dimmer to skip: it shades direct light each frame"},
            {"pathtrace", "progressive: a light change restarts its accumulation"}});
}

}  // namespace dimmer_test
}  // namespace gistream
