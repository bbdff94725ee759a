// The white furnace over every solver (issue 14): the bundled closed 2 m
// cube, every wall emitting L_e = 1 with albedo rho, so the exact answer
// is L = 1 / (1 - rho) at every pixel (`direct`: one bounce, 1 + rho). Each
// solver runs to convergence (tolerance 1e-4, its count as a cap far
// above what that needs) and the image mean must be within the solver's
// stated tolerance of the exact value, and never above it by more than
// the tolerance (no solver may create energy). docs/RESULTS.md's furnace
// table lists the measured values; the tolerances below are those values
// with a margin, and say what is still lost where the target
// (rho = 0.9 within 2 %, 0.99 within 5 %) is not reached. FurnaceAtDefaults
// (below) runs the solvers at their defaults.
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
namespace furnace_test {

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

// The exact radiance of case c: 1 / (1 - rho), `direct` 1 + rho.
double Exact(const FurnaceCase& c) {
  const double rho = double(c.rho);
  return std::string(c.solver) == "direct" ? 1.0 + rho : 1.0 / (1.0 - rho);
}

// The furnace's mean radiance (green) for `solver` with `params` at albedo
// rho (16 x 16 pixels, finite, grey).
double FurnaceMean(const std::string& solver, const std::map<std::string, std::string>& params,
                   float rho) {
  const BundledCopy scene("furnace.gltf");
  EncodedFrame frame;
  const FloatImage image = RenderRequestExr(
      SolverRequest(scene.id(), solver, params, 16, {{1, GreyAlbedo(rho)}}), &frame);
  EXPECT_EQ(image.width, 16);
  EXPECT_EQ(image.non_finite(), 0u);
  const double mean = ImageMean(image).g;
  EXPECT_NEAR(ImageMean(image).r, mean, 1e-6 * mean);  // grey stays grey
  return mean;
}

TEST_P(Furnace, ConvergesToTheExactRadiance) {
  const FurnaceCase& c = GetParam();
  const double exact = Exact(c);
  const double mean = FurnaceMean(c.solver, c.params, c.rho);
  testing::RecordMeasurement(absl::StrCat("mean_rho_", c.rho), mean);
  testing::RecordMeasurement(absl::StrCat("exact_rho_", c.rho), exact);
  EXPECT_NEAR(mean, exact, c.tolerance * exact);
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
    // sh_probes: measured +0.08, -0.16, -0.6 % (-3.1 % at 0.99 while the
    // probes' albedo was a half float, probe_grid.cpp).
    FurnaceCase{"sh_probes", 0.5f, kShProbes, 0.01},
    FurnaceCase{"sh_probes", 0.9f, kShProbes, 0.01},
    FurnaceCase{"sh_probes", 0.99f, kShProbes, 0.015},
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

// At each solver's defaults (issue 29, item 4): what a user gets without
// raising a cap. The targets: rho = 0.9 within 2 %, 0.99 within 5 %, 0.999
// within 20 %, monotone in the iteration count. Before the geometric tail
// (solvers/tail_estimate.h) was on by default the iterative solvers
// stopped at their tolerance or cap: at 0.9 sh_probes 0.935, implicit_
// visibility 0.937, antiradiance 0.964, avg 0.654 of the exact value; at
// 0.99 0.29 / 0.29 / 0.29 / 0.10; at 0.999 0.033 / 0.033 / 0.033 / 0.010.
// Tolerances below: the targets, which every solver meets.
class FurnaceAtDefaults : public ::testing::TestWithParam<FurnaceCase> {};

TEST_P(FurnaceAtDefaults, ReachesTheExactRadiance) {
  const FurnaceCase& c = GetParam();
  const double exact = Exact(c);
  const double mean = FurnaceMean(c.solver, {}, c.rho);
  testing::RecordMeasurement("ratio", mean / exact);
  EXPECT_NEAR(mean, exact, c.tolerance * exact) << c.solver << ": " << mean / exact << "x";
}

const std::vector<FurnaceCase> kDefaultsCases = {
    // 0.3 %: the G-buffer's 8-bit albedo.
    {"direct", 0.9f, {}, 0.003},
    {"direct", 0.999f, {}, 0.003},
    // Measured 1.0004 / 0.996 / 0.996 after 5-6 bounces (TailResidual
    // ends the solve; were 0.9996 / 0.972 / 0.681 while the probes' albedo
    // was a half float, truncated to 0.998535 for 0.999: probe_grid.cpp).
    {"sh_probes", 0.9f, {}, 0.02},
    {"sh_probes", 0.99f, {}, 0.05},
    {"sh_probes", 0.999f, {}, 0.20},
    // Measured 1.002 / 0.998 / 1.001.
    {"implicit_visibility", 0.9f, {}, 0.02},
    {"implicit_visibility", 0.99f, {}, 0.05},
    {"implicit_visibility", 0.999f, {}, 0.20},
    // Measured 0.992 / 0.986 / 0.988.
    {"antiradiance", 0.9f, {}, 0.02},
    {"antiradiance", 0.99f, {}, 0.05},
    {"antiradiance", 0.999f, {}, 0.20},
    // Measured 1.013 / 1.031 / 1.030 with the tail spread over the last
    // four generations (0.968 / 0.950 / 0.929 on the last one alone: its
    // few VPLs, 86 of 1024 at 0.9, carried most of the light, and a view
    // gathered a varying share of it).
    {"avg", 0.9f, {}, 0.02},
    {"avg", 0.99f, {}, 0.05},
    {"avg", 0.999f, {}, 0.20},
};

INSTANTIATE_TEST_SUITE_P(EverySolver, FurnaceAtDefaults, ::testing::ValuesIn(kDefaultsCases),
                         [](const ::testing::TestParamInfo<FurnaceCase>& p) {
                           return std::string(p.param.solver) + "_rho" +
                                  std::to_string(int(std::lround(double(p.param.rho) * 1000.0)));
                         });

// More iterations never give less (MonotoneTailFactor: each bounce's
// partial sum plus its tail is at most the albedo bound's fixed point, and
// the largest of them is kept), at rho = 0.999 where the tail is most of
// the answer.
TEST(FurnaceAtDefaults, MonotoneInTheIterationCount) {
  for (const auto& [solver, count] : std::map<std::string, std::string>{
           {"implicit_visibility", "bounces"}, {"antiradiance", "iterations"}}) {
    double last = 0.0;
    for (const char* n : {"8", "16", "32"}) {
      const double mean = FurnaceMean(solver, {{count, n}}, 0.999f);
      testing::RecordMeasurement(absl::StrCat(solver, "_", n), mean);
      EXPECT_GE(mean, last * (1.0 - 1e-4)) << solver << " at " << count << " = " << n;
      last = mean;
    }
  }
}

TEST(FurnaceAtDefaults, CoversEveryRegisteredSolver) {
  std::set<std::string> run;
  for (const FurnaceCase& c : kDefaultsCases) run.insert(c.solver);
  testing::ExpectCoversEveryRegisteredSolver(
      run, {{"pathtrace",
             "unbiased and unbounded in depth at its defaults (one sample a frame): its furnace "
             "at 64 spp is Furnace.*"}});
}

}  // namespace furnace_test
}  // namespace gistream
