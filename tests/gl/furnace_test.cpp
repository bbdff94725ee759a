// The white furnace over every solver (issue 14): the bundled closed 2 m
// cube, every wall emitting L_e = 1 with albedo rho, so the exact answer
// is L = 1 / (1 - rho) at every pixel (`direct`: one bounce, 1 + rho). Each
// solver runs to convergence (tolerance 1e-4, its count as a cap far
// above what that needs) and the image mean must be within the solver's
// stated tolerance of the exact value, and never above it by more than
// the tolerance (no solver may create energy). docs/RESULTS.md's furnace
// table lists the measured values; the tolerances below are those values
// with a margin, and say what is still lost where the target
// (rho = 0.9 within 2 %, 0.99 within 5 %) is not reached.
#include <cmath>
#include <map>
#include <set>
#include <string>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "support/measurement.h"
#include "support/render_helpers.h"
#include "support/registered_solvers.h"

namespace gistream {
namespace {

using testing::BundledCopy;
using testing::FloatImage;
using testing::GreyAlbedo;
using testing::ImageMean;
using testing::RenderRequestExr;
using testing::SolverRequest;

struct FurnaceCase {
  const char* solver;
  float rho;
  std::map<std::string, std::string> params;
  double tolerance;  // relative to the exact value
};

void PrintTo(const FurnaceCase& c, std::ostream* os) { *os << c.solver << " rho " << c.rho; }

class Furnace : public ::testing::TestWithParam<FurnaceCase> {};

TEST_P(Furnace, ConvergesToTheExactRadiance) {
  const FurnaceCase& c = GetParam();
  const double rho = double(c.rho);
  const bool one_bounce = std::string(c.solver) == "direct";
  const double exact = one_bounce ? 1.0 + rho : 1.0 / (1.0 - rho);
  const BundledCopy scene("furnace.gltf");
  EncodedFrame frame;
  const FloatImage image = RenderRequestExr(
      SolverRequest(scene.id(), c.solver, c.params, 16, {{1, GreyAlbedo(c.rho)}}), &frame);
  ASSERT_EQ(image.width, 16);
  EXPECT_EQ(image.non_finite(), 0u);
  const double mean = ImageMean(image).g;
  testing::RecordMeasurement(absl::StrCat("mean_rho_", rho), mean);
  testing::RecordMeasurement(absl::StrCat("exact_rho_", rho), exact);
  EXPECT_NEAR(mean, exact, c.tolerance * exact);
  EXPECT_NEAR(ImageMean(image).r, mean, 1e-6 * exact);  // grey stays grey
}

// Iterative solvers: tolerance 1e-4 with a cap they do not reach (the
// residual falls by about rho per iteration: ~320 at rho = 0.99).
const std::map<std::string, std::string> kIterated = {{"tolerance", "1e-4"}, {"bounces", "4096"}};
const std::map<std::string, std::string> kAntiradiance = {{"tolerance", "1e-4"},
                                                          {"iterations", "4096"}};
// sh_probes' bounces cost a probe re-render each: 32 bounces and the
// geometric tail for the rest (tail_estimate.h), on a 4^3 grid.
const std::map<std::string, std::string> kShProbes = {
    {"grid", "4"}, {"bounces", "32"}, {"tolerance", "1e-4"}, {"tail_estimate", "true"}};
// avg: the most VPLs, and Keller's split capped only far out.
const std::map<std::string, std::string> kAvg = {{"vpls", "2048"}, {"bounces", "1024"}};

const std::vector<FurnaceCase> kFurnaceCases = {
    // direct: the exact polygon term times the samples' visibility
    // ratio (render/direct_light.glsl) gives pi inside the closed box;
    // 0.3 %: the G-buffer's 8-bit albedo (0.9 is shaded as 230/255,
    // +0.2 %) and the few pixels a shadow lookup falsely occludes.
    FurnaceCase{"direct", 0.5f, {}, 0.003}, FurnaceCase{"direct", 0.9f, {}, 0.003},
    FurnaceCase{"direct", 0.99f, {}, 0.003},
    // pathtrace: 16,384 paths (64 spp x 256 pixels) with Russian
    // roulette; the per-path standard deviation is about L, so the
    // standard error is ~0.8 % of L; 2 % is more than two of them
    // (measured -0.1, -0.4, +0.1 %).
    FurnaceCase{"pathtrace", 0.5f, {{"spp", "64"}}, 0.02},
    FurnaceCase{"pathtrace", 0.9f, {{"spp", "64"}}, 0.02},
    FurnaceCase{"pathtrace", 0.99f, {{"spp", "64"}}, 0.03},
    // sh_probes: measured +0.1, -0.3, -3.1 %; the tail's ratio is capped
    // at 0.99 (tail_estimate.h), which is what is left at 0.99.
    FurnaceCase{"sh_probes", 0.5f, kShProbes, 0.01},
    FurnaceCase{"sh_probes", 0.9f, kShProbes, 0.01},
    FurnaceCase{"sh_probes", 0.99f, kShProbes, 0.05},
    // implicit_visibility: measured +0.2, +0.1, -1.1 %. Each bounce
    // gathers 99.99 % of what a closed box sends (bins that meet an
    // element's disc count as covered, refine_push.cpp; it was 99.54 %,
    // -36 % at 0.99), and 1 / (1 - rho k) multiplies what is left.
    FurnaceCase{"implicit_visibility", 0.5f, kIterated, 0.01},
    FurnaceCase{"implicit_visibility", 0.9f, kIterated, 0.01},
    FurnaceCase{"implicit_visibility", 0.99f, kIterated, 0.03},
    // antiradiance: measured -0.07, -0.8, -1.1 % (were -0.1, -1.4,
    // -9.0 %, and -1.2, -19, -74 % before that): the near leaves'
    // exact form factors, and every farther link's Eq. 17 kernel
    // averaged over both ends' sigma points (links.cpp; a closed
    // box gathers 99.93 % per pass, was 99.88 %). At 0.99 a change
    // of 1e-4 per pass moves the mean by 1 %, hence 3 %: within the
    // issue's 5 %, and never above the exact value by more.
    FurnaceCase{"antiradiance", 0.5f, kAntiradiance, 0.01},
    FurnaceCase{"antiradiance", 0.9f, kAntiradiance, 0.02},
    FurnaceCase{"antiradiance", 0.99f, kAntiradiance, 0.03},
    // avg: VPL paths end by Keller's split, and no ray leaves the
    // shell (rays stop on the voxels' sheets: AvgClosedBoxRays), so
    // the VPLs carry the split's truncated series exactly
    // (AvgStiffFurnace): -0.02 % / -0.2 % / -2.5 % of the full
    // series at 0.5 / 0.9 / 0.99 (2048 VPLs: 20 paths reach 368
    // bounces at 0.99). Measured +0.07, +0.8, -3.5 % (were -0.0,
    // +0.8, -14.5 % when 0.2-0.8 % of rays escaped); the image adds
    // about 1 % either way to its VPLs' flux (+1.0 % at 0.9, -1.0 %
    // at 0.99), hence 0.5 % / 1.5 % / 5 % (the target).
    FurnaceCase{"avg", 0.5f, kAvg, 0.005}, FurnaceCase{"avg", 0.9f, kAvg, 0.015},
    FurnaceCase{"avg", 0.99f, kAvg, 0.05}};

INSTANTIATE_TEST_SUITE_P(EverySolver, Furnace, ::testing::ValuesIn(kFurnaceCases),
                         [](const ::testing::TestParamInfo<FurnaceCase>& p) {
                           return std::string(p.param.solver) + "_rho" +
                                  std::to_string(int(std::lround(double(p.param.rho) * 100.0)));
                         });

TEST(Furnace, CoversEveryRegisteredSolver) {
  std::set<std::string> run;
  for (const FurnaceCase& c : kFurnaceCases) run.insert(c.solver);
  testing::ExpectCoversEveryRegisteredSolver(run, {});
}

}  // namespace
}  // namespace gistream
