// One suite over every registered solver (solvers/registry.h): each solver
// declares, with its reason, how close to the path-traced reference it
// comes and how invariant it is to scale and intensity; a solver missing
// from the table fails. Stochastic solvers also pass a z-test of their
// furnace mean. Method-specific checks stay in each solver's own file.
#include <cmath>
#include <map>
#include <memory>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "solvers/registry.h"
#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace all_solvers_test {

using testing::BundledCopy;
using testing::FloatImage;
using testing::RenderRequestExr;
using testing::SolverRequest;

struct Declared {
  // indirect_room (all light indirect) at 64 x 64 and default parameters:
  // relMSE against the 1024-spp reference at most this fraction of
  // `direct`'s (1: no better than direct is required).
  double indirect_room_vs_direct = 1.0;
  std::string indirect_room_reason;
  // The furnace (albedo 0.5) from millimetres to kilometres and 1e-3 to
  // 1e6 nits: mean / strength within this of the exact value (2, or 1.5
  // for a direct-only solver).
  double furnace_tolerance = 0.1;
  std::string furnace_reason;
  std::map<std::string, std::string> furnace_params;
  bool direct_only = false;
  bool stochastic = false;  // gets the z-test
};

const std::map<std::string, Declared>& Table() {
  static const std::map<std::string, Declared> table = {
      {"direct",
       {1.0,
        "direct light only: room B stays black, this is the baseline",
        0.01,
        "the exact unoccluded term of the emitter (a closed sphere): only float rounding and the "
        "8-bit albedo (measured 1.50196 at every scale)",
        {},
        /*direct_only=*/true}},
      {"pathtrace",
       {0.25,
        "the reference's own estimator at 256 spp: only its noise differs (relMSE of "
        "noise ~ 1/spp: measured 0.021 against direct's 0.145)",
        0.05,
        "Monte Carlo noise of 64 spp at 16 x 16, the same samples at every scale (measured "
        "1.9976 at every scale; the z-test below is the real check)",
        {{"spp", "64"}},
        false,
        /*stochastic=*/true}},
      {"sh_probes",
       {0.2,
        "probes carry the light through the doorway; SH l <= 2 and probe spacing blur room B "
        "(measured 0.017 against direct's 0.145)",
        0.02,
        "12 bounces of 0.5 (0.02 %) and the l <= 2 projection of a constant (exact): measured "
        "2.0015 at every scale",
        {{"grid", "4"}, {"bounces", "12"}, {"tolerance", "0"}}}},
      {"avg",
       {0.4,
        "VPLs light room B; 64^2 VPL maps and their shadow bias at the door reveals "
        "(measured 0.043 against direct's 0.145)",
        0.02,
        "VPL flux is exact on the closed furnace at any grid size and scale (AvgGridFlux); the "
        "mean "
        "is 1.9991 at scale 1 (1.9966 before rays stopped on the voxels' sheets) and was within "
        "0.06 % of it from 1e-4 to 1e5 (docs/RESULTS.md scale table; was 6 % low at 1e-3 from a "
        "voxelization rounding gap, fixed)",
        {}}},
      {"implicit_visibility",
       {0.2,
        "links carry the light through the door, bounces until the residual tolerance "
        "(issue 14: at least 5x better than direct; measured 0.020 against 0.145)",
        0.02,
        "solid angles and disc form factors are scale-free; 12 bounces of 0.5 (measured 2.0000 "
        "at every scale)",
        {{"bounces", "12"}, {"bins_per_face", "8"}}}},
      {"antiradiance",
       {0.2,
        "unoccluded transport minus antiradiance keeps the light out of the wall "
        "(measured 0.019 against direct's 0.145)",
        0.02,
        "Eq. 17's 1/r^2 and the cells' form factors scale, the answer does not; 8 iterations of "
        "0.5 and 99.88 % per pass (measured 1.9963 at every scale; it was 10 % before issue 14)",
        {{"iterations", "8"}}}},
  };
  return table;
}

std::vector<std::string> RegisteredSolvers() {
  std::vector<std::string> names;
  for (const SolverDescription& d : AllSolverDescriptions()) names.push_back(d.name);
  return names;
}

std::vector<std::string> StochasticNames() {
  std::vector<std::string> names;
  for (const std::string& name : RegisteredSolvers()) {
    if (Table().contains(name) && Table().at(name).stochastic) names.push_back(name);
  }
  return names;
}

TEST(AllSolversTable, DeclaresEveryRegisteredSolver) {
  for (const std::string& name : RegisteredSolvers()) {
    EXPECT_TRUE(Table().contains(name))
        << name << " declares no tolerances in all_solvers_test.cpp";
  }
}

class AllSolvers : public ::testing::TestWithParam<std::string> {
 protected:
  const Declared& declared() const {
    static const Declared none;
    const auto it = Table().find(GetParam());
    return it == Table().end() ? none : it->second;
  }
};

// indirect_room and its reference, rendered once for every solver.
struct IndirectRoom {
  BundledCopy scene{"indirect_room.gltf"};
  FloatImage reference;
  double direct_error = 0.0;
};
// Never destroyed: the shared engine goes first, when the test program
// ends, and the scene with it.
const IndirectRoom& Room() {
  static const IndirectRoom* const room = [] {
    auto* r = new IndirectRoom();
    r->reference =
        RenderRequestExr(SolverRequest(r->scene.id(), "pathtrace", {{"spp", "1024"}}, 64));
    r->direct_error = testing::RelMse(
        RenderRequestExr(SolverRequest(r->scene.id(), "direct", {}, 64)), r->reference);
    return r;
  }();
  return *room;
}

TEST_P(AllSolvers, IndirectRoomAgainstTheReference) {
  const IndirectRoom& room = Room();
  const std::map<std::string, std::string> params =
      GetParam() == "pathtrace" ? std::map<std::string, std::string>{{"spp", "256"}}
                                : std::map<std::string, std::string>{};
  const FloatImage image = RenderRequestExr(SolverRequest(room.scene.id(), GetParam(), params, 64));
  EXPECT_EQ(image.non_finite(), 0u);
  const double error = testing::RelMse(image, room.reference);
  testing::RecordMeasurement("relmse", error);
  testing::RecordMeasurement("relmse_direct", room.direct_error);
  EXPECT_LE(error, declared().indirect_room_vs_direct * room.direct_error * (1.0 + 1e-9))
      << declared().indirect_room_reason;
}

TEST_P(AllSolvers, FurnaceIsScaleAndIntensityInvariant) {
  testing::ExpectFurnaceScaleInvariant(GetParam(), declared().furnace_params,
                                       declared().furnace_tolerance, {},
                                       declared().direct_only ? 1.5 : 2.0);
}

// Mitsuba-style z-test of a stochastic solver: the furnace's per-pixel
// estimates are independent samples of L = E / (1 - rho) = 2; their mean
// may stray from 2 by no more than 4 standard errors (a false alarm once
// in ~16,000 runs; a 1 % bias at these settings is ~10 standard errors).
class StochasticSolvers : public AllSolvers {};

TEST_P(StochasticSolvers, FurnaceMeanPassesAZTest) {
  const BundledCopy scene("furnace.gltf");
  const FloatImage image =
      RenderRequestExr(SolverRequest(scene.id(), GetParam(), {{"spp", "16"}}, 64));
  ASSERT_EQ(image.non_finite(), 0u);
  const size_t n = size_t(image.width) * size_t(image.height);
  double sum = 0.0, sum_sq = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double v = image.rgba[i * 4 + 1];
    sum += v;
    sum_sq += v * v;
  }
  const double mean = sum / double(n);
  const double variance = (sum_sq - double(n) * mean * mean) / double(n - 1);
  const double standard_error = std::sqrt(std::max(variance, 0.0) / double(n));
  ASSERT_GT(standard_error, 0.0) << "no noise at all: not a per-pixel estimate";
  const double z = (mean - 2.0) / standard_error;
  testing::RecordMeasurement("mean", mean);
  testing::RecordMeasurement("standard_error", standard_error);
  testing::RecordMeasurement("z", z);
  EXPECT_LT(std::abs(z), 4.0);
}

INSTANTIATE_TEST_SUITE_P(Registered, AllSolvers, ::testing::ValuesIn(RegisteredSolvers()),
                         [](const ::testing::TestParamInfo<std::string>& param_info) {
                           return param_info.param;
                         });
// Only the solvers declared stochastic get the z-test (the others'
// per-pixel values are not independent samples).
INSTANTIATE_TEST_SUITE_P(Registered, StochasticSolvers, ::testing::ValuesIn(StochasticNames()),
                         [](const ::testing::TestParamInfo<std::string>& param_info) {
                           return param_info.param;
                         });

}  // namespace all_solvers_test
}  // namespace gistream
