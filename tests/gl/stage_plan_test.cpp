// One test over every registered solver: for each kind of change (the
// first frame, every light dimmed by one factor, a punctual light recoloured, an emitter lit, a
// base colour, a camera move, a moved node) the engine asks the solver for its plan, the stages of
// the solver's table that ran are exactly the planned ones, every stage of the table is reported
// (run or skipped), and the plan matches the kind of change (the first frame plans every stage; a
// camera move plans no view-independent one).
#include <algorithm>
#include <set>

#include <gtest/gtest.h>

#include "solvers/registry.h"
#include "support/render_helpers.h"

namespace gistream {
namespace stage_plan_test {

using testing::BundledCopy;

// Small, cheap settings per solver (the plan does not depend on them).
std::map<std::string, std::string> CheapParams(const std::string& solver) {
  if (solver == "direct") return {{"area_samples", "4"}, {"shadow_res", "32"}};
  if (solver == "pathtrace") return {{"spp", "1"}};
  if (solver == "sh_probes")
    return {{"grid", "3"}, {"face_size", "4"}, {"area_samples", "4"}, {"shadow_res", "32"}};
  if (solver == "avg")
    return {{"vpls", "32"},
            {"grid", "8"},
            {"shadow_res", "8"},
            {"area_samples", "4"},
            {"direct_shadow_res", "32"}};
  if (solver == "implicit_visibility")
    return {{"bins_per_face", "2"}, {"area_samples", "4"}, {"shadow_res", "32"}};
  if (solver == "antiradiance")
    return {{"bins", "32"}, {"iterations", "1"}, {"area_samples", "4"}, {"shadow_res", "32"}};
  return {};
}

struct Step {
  std::string name;
  std::vector<Update> updates;
  std::optional<CameraUpdate> camera;
};

std::vector<Step> Steps() {
  // dynamic_block: light 0 point light, light 1 sun, material 2 the block,
  // node 2 the block. Its lights are punctual; the emitter step uses an
  // emissive material set on the back wall (material 1).
  LightUpdate recolour;
  recolour.light = 0;
  recolour.color = glm::vec3(1.0f, 0.5f, 0.25f);
  MaterialUpdate glow;
  glow.material = 1;
  glow.emissive = glm::vec3(0.2f, 0.4f, 0.1f);
  glow.emissive_strength = 1.0f;
  MaterialUpdate paint;
  paint.material = 2;
  paint.base_color = glm::vec4(0.2f, 0.7f, 0.3f, 1.0f);
  CameraUpdate camera;
  camera.look_at = LookAt{{1.0f, 2.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  // Both lights at half their intensity (30 and 1 in dynamic_block.gltf):
  // a dimmer, which GI solvers show by scaling their last solution
  // (solvers/emission_scale.h) instead of solving again.
  LightUpdate dim_point, dim_sun;
  dim_point.light = 0;
  dim_point.intensity = 15.0f;
  dim_sun.light = 1;
  dim_sun.intensity = 0.5f;
  NodeTransformUpdate move;
  move.node = 2;
  move.translation = {0.5f, 0.25f, 0.3f};
  return {{"first", {}, std::nullopt},
          {"dimmer", {{1, dim_point}, {2, dim_sun}}, std::nullopt},
          {"light", {{3, recolour}}, std::nullopt},
          {"emission", {{4, glow}}, std::nullopt},
          {"material", {{5, paint}}, std::nullopt},
          {"camera", {}, camera},
          {"geometry", {{6, move}}, std::nullopt}};
}

class StagePlan : public ::testing::TestWithParam<std::string> {};

TEST_P(StagePlan, StagesThatRunAreThePlannedOnes) {
  const std::string solver = GetParam();
  const auto description = FindSolver(solver);
  ASSERT_TRUE(description.ok()) << description.status();
  const std::vector<std::string>& table = (*description)->stages;
  std::set<std::string> first_plan;

  const BundledCopy scene("dynamic_block.gltf");
  for (const Step& step : Steps()) {
    RenderRequest request =
        testing::SolverRequest(scene.id(), solver, CheapParams(solver), 16, step.updates);
    // The camera step looks from elsewhere; the others from the default.
    if (step.camera) request.camera = step.camera;
    EncodedFrame frame;
    testing::RenderRequestExr(request, &frame);
    std::set<std::string> ran;
    for (const std::string& stage : table) {
      const StageTiming* t = testing::FrameStage(frame, stage);
      ASSERT_NE(t, nullptr) << solver << ", " << step.name << ": stage " << stage
                            << " not reported";
      if (!t->skipped) ran.insert(stage);
    }
    const std::set<std::string> planned(frame.planned_stages.begin(), frame.planned_stages.end());
    EXPECT_EQ(ran, planned) << solver << ", " << step.name;
    if (step.name == "first") {
      first_plan = planned;
      EXPECT_EQ(planned, std::set<std::string>(table.begin(), table.end())) << solver;
    } else {
      // No change needs more than the first frame did.
      EXPECT_TRUE(
          std::includes(first_plan.begin(), first_plan.end(), planned.begin(), planned.end()))
          << solver << ", " << step.name;
    }
  }
}

std::vector<std::string> RegisteredSolvers() {
  std::vector<std::string> names;
  for (const SolverDescription& d : AllSolverDescriptions()) names.push_back(d.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, StagePlan, ::testing::ValuesIn(RegisteredSolvers()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace stage_plan_test
}  // namespace gistream
