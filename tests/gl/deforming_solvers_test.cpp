// Every solver on the bundled deforming scenes (issue 18): bending_tube (a
// skinned tube swaying in a Cornell box) and morph_blob (a morph-target
// sphere), each paused at a deformed still frame by an animation seek. Each
// solver's image is finite and within its declared relMSE of the path-traced
// reference at the same pose, and a solver that solved the rest pose and is
// then seeked agrees with a fresh solve of the posed scene (its update path
// for a deformation change loses nothing).
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <set>
#include <string>

#include "support/deforming_scene.h"
#include "support/measurement.h"
#include "support/render_helpers.h"
#include "support/registered_solvers.h"

namespace gistream {
namespace deforming_solvers_test {

using testing::BundledCopy;
using testing::FloatImage;
using testing::RenderRequestExr;
using testing::SolverRequest;

constexpr uint32_t kSize = 64;

struct Case {
  const char* file;
  float pose;  // seconds into the scene's animation: the still frame
};
// bending_tube at 1 s: bent 30 degrees; morph_blob at 1 s: squash 1,
// ripple 0.5 (tools/make_scenes.py).
const Case kCases[] = {{"bending_tube.gltf", 1.0f}, {"morph_blob.gltf", 1.0f}};

// A measurement's key: the scene's file name without ".gltf", then `what`.
std::string Key(const Case& c, const std::string& what) {
  const std::string file = c.file;
  return file.substr(0, file.rfind('.')) + "." + what;
}

// relMSE against the 512-spp reference at 64 x 64, at most: about twice
// what was measured (in the reasons: bending_tube, morph_blob), so a
// solver that ignored the pose (the reference's tube or blob drawn where
// the solver's is not) fails; both scenes are Cornell boxes lit from the
// ceiling, where direct light alone is 0.06-0.08 off.
struct Declared {
  double max_rel_mse;
  const char* reason;
  std::map<std::string, std::string> params;
};
const std::map<std::string, Declared>& Table() {
  static const std::map<std::string, Declared> table = {
      {"direct", {0.15, "no indirect light at all: the baseline (measured 0.076, 0.063)", {}}},
      {"pathtrace",
       {0.005,
        "its own estimator at 128 spp: noise only (measured 0.0015, 0.0013)",
        {{"spp", "128"}}}},
      {"sh_probes",
       {0.02, "SH l <= 2 probes blur the contact shadows (measured 0.0095, 0.0095)", {}}},
      {"avg", {0.03, "VPL maps at their default resolution (measured 0.014, 0.012)", {}}},
      {"implicit_visibility",
       {0.02, "elements moved to the posed mesh and relinked (measured 0.0097, 0.0085)", {}}},
      {"antiradiance", {0.02, "patches on the posed mesh, relinked (measured 0.0092, 0.0088)", {}}},
  };
  return table;
}

class DeformingSolvers : public ::testing::TestWithParam<std::string> {};

// Each case's 512-spp path-traced reference, rendered once per test binary
// (ctest runs the suite in one process) on its own copy of the scene.
const FloatImage& Reference(const Case& c) {
  static auto* const cache = new std::map<std::string, FloatImage>();
  auto it = cache->find(c.file);
  if (it == cache->end()) {
    const BundledCopy scene(c.file);
    it = cache
             ->emplace(c.file,
                       RenderRequestExr(SolverRequest(scene.id(), "pathtrace", {{"spp", "512"}},
                                                      kSize, {testing::SeekAnimation(1, c.pose)})))
             .first;
  }
  return it->second;
}

TEST_P(DeformingSolvers, StillFrameIsFiniteAndNearTheReference) {
  const Declared& declared = Table().at(GetParam());
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.file);
    const BundledCopy scene(c.file);
    const FloatImage& reference = Reference(c);
    EncodedFrame frame;
    const FloatImage image =
        RenderRequestExr(SolverRequest(scene.id(), GetParam(), declared.params, kSize,
                                       {testing::SeekAnimation(2, c.pose)}),
                         &frame);
    ASSERT_EQ(image.width, int(kSize));
    EXPECT_EQ(image.non_finite(), 0u);
    const double error = testing::RelMse(image, reference);
    testing::RecordMeasurement(Key(c, "rel_mse"), error);
    EXPECT_LE(error, declared.max_rel_mse) << declared.reason;
  }
}

// The update path is the same at any size of the solver's data: sh_probes
// with 4^3 probes instead of 8^3 (its default solves took 40 s of the
// suite's 100 s on llvmpipe, three per case).
std::map<std::string, std::string> SeekParams(const std::string& solver) {
  std::map<std::string, std::string> params = Table().at(solver).params;
  if (solver == "sh_probes") params["grid"] = "4";
  return params;
}

TEST_P(DeformingSolvers, SeekedSolveEqualsAFreshSolveOfThePose) {
  const std::map<std::string, std::string> params = SeekParams(GetParam());
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.file);
    const BundledCopy updated(c.file);
    const FloatImage rest =
        RenderRequestExr(SolverRequest(updated.id(), GetParam(), params, kSize));
    EncodedFrame frame;
    const FloatImage seeked = RenderRequestExr(
        SolverRequest(updated.id(), GetParam(), params, kSize, {testing::SeekAnimation(1, c.pose)}),
        &frame);
    const BundledCopy fresh(c.file);
    const FloatImage direct = RenderRequestExr(
        SolverRequest(fresh.id(), GetParam(), params, kSize, {testing::SeekAnimation(1, c.pose)}));
    // The frame after the seek posed the mesh on the GPU.
    const StageTiming* deform = testing::FrameStage(frame, "deform");
    ASSERT_NE(deform, nullptr);
    EXPECT_FALSE(deform->skipped);
    // Same pose, same parameters: the same solution up to the order of
    // float sums (progressive and background updates split the work).
    const double error = testing::RelMse(seeked, direct);
    testing::RecordMeasurement(Key(c, "seeked_vs_fresh_rel_mse"), error);
    EXPECT_LE(error, 1e-3);
    // And the pose is seen: the tube bent 60 degrees at the top, the blob
    // squashed (relMSE against the rest pose measured 0.12-0.14 for the
    // tube, 0.019-0.023 for the blob).
    const double moved = testing::RelMse(seeked, rest);
    testing::RecordMeasurement(Key(c, "posed_vs_rest_rel_mse"), moved);
    EXPECT_GE(moved, 0.01);
  }
}

INSTANTIATE_TEST_SUITE_P(Registered, DeformingSolvers,
                         ::testing::ValuesIn(testing::RegisteredSolverNames()),
                         [](const ::testing::TestParamInfo<std::string>& param_info) {
                           return param_info.param;
                         });

}  // namespace deforming_solvers_test
}  // namespace gistream
