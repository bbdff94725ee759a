// The iterative solvers' geometric tail estimate (solvers/tail_estimate.h):
// never above what the measured bounce ratios support.
#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/tail_estimate.h"

namespace gistream {
namespace tail_estimate_test {

std::vector<double> Geometric(double first, double r, int n) {
  std::vector<double> d;
  for (int k = 0; k < n; ++k) d.push_back(first * std::pow(r, k));
  return d;
}

TEST(TailEstimate, ExactGeometricSeriesGivesItsRatio) {
  const TailEstimate t = EstimateTail(Geometric(1.0, 0.9, 6));
  EXPECT_TRUE(t.applied);
  EXPECT_NEAR(t.ratio, 0.9, 1e-12);
  EXPECT_EQ(t.ratios, 3);
  EXPECT_NEAR(t.spread, 0.0, 1e-12);
}

TEST(TailEstimate, TakesTheSmallestRecentRatio) {
  // Ratios 0.90, 0.92, 0.91 (within 5 %): the tail uses 0.90, never more.
  const std::vector<double> d = {
      1.0, 0.9, 0.81, 0.81 * 0.90, 0.81 * 0.90 * 0.92, 0.81 * 0.90 * 0.92 * 0.91};
  const TailEstimate t = EstimateTail(d);
  EXPECT_TRUE(t.applied);
  EXPECT_NEAR(t.ratio, 0.90, 1e-12);
}

TEST(TailEstimate, RatioNearOneIsCapped) {
  // rho = 0.99999: r / (1 - r) would be 99999 x the last increment; capped
  // at 0.9999, i.e. 9999 x.
  const TailEstimate t = EstimateTail(Geometric(1.0, 0.99999, 5));
  EXPECT_TRUE(t.applied);
  EXPECT_DOUBLE_EQ(t.ratio, kMaxTailRatio);
}

TEST(TailEstimate, RatioIsNeverAboveTheScenesLargestAlbedo) {
  // Measured ratios 0.9995 (rounding) in a scene whose largest albedo is
  // 0.999: the tail takes 0.999 (999 x, not 1999 x the last increment).
  const TailEstimate t = EstimateTail(Geometric(1.0, 0.9995, 6), 0.999);
  EXPECT_TRUE(t.applied);
  EXPECT_DOUBLE_EQ(t.ratio, 0.999);
  // Below the bound the measured ratio stands.
  EXPECT_NEAR(EstimateTail(Geometric(1.0, 0.9, 6), 0.999).ratio, 0.9, 1e-12);
  // A black scene has no tail to add.
  EXPECT_EQ(EstimateTail(Geometric(1.0, 0.9, 6), 0.0).ratio, 0.0);
}

TEST(TailEstimate, UnstableOrDivergingOrTooFewRatiosGiveNoTail) {
  EXPECT_FALSE(EstimateTail({1.0, 0.5, 0.25}).applied);        // one usable ratio
  EXPECT_FALSE(EstimateTail({1.0, 0.5, 0.4, 0.2}).applied);    // 0.8 then 0.5
  EXPECT_FALSE(EstimateTail({1.0, 0.9, 0.95, 0.97}).applied);  // growing: ratio >= 1
  EXPECT_FALSE(EstimateTail({1.0, 0.0, 0.0, 0.0}).applied);    // converged to nothing
  EXPECT_FALSE(EstimateTail({1.0, 0.5, NAN, 0.2}).applied);
  EXPECT_EQ(EstimateTail({1.0, 0.5, 0.4, 0.2}).ratio, 0.0);
}

TEST(TailEstimate, FixedPointIsNeverOvershotForAnySeriesBelowTheCap) {
  // For a geometric series of ratio rho, partial sum + tail must not exceed
  // the exact sum d_1 / (1 - rho) for any number of bounces >= 2, and must
  // grow with the number of bounces (monotone); the scene's albedo bound is
  // rho itself.
  for (double rho : {0.5, 0.9, 0.99, 0.999}) {
    const double exact = 1.0 / (1.0 - rho);
    double previous = 0.0;
    for (int n = 2; n <= 64; ++n) {
      const std::vector<double> d = Geometric(1.0, rho, n);
      double sum = 0.0;
      for (double x : d) sum += x;
      const TailEstimate t = EstimateTail(d, rho);
      const double total = sum + (t.applied ? t.ratio / (1.0 - t.ratio) * d.back() : 0.0);
      EXPECT_LE(total, exact * (1.0 + 1e-9)) << "rho " << rho << " n " << n;
      EXPECT_GE(total, previous * (1.0 - 1e-12)) << "rho " << rho << " n " << n;
      previous = total;
    }
  }
}

TEST(TailEstimate, MonotoneFactorNeverLowersTheEstimateWhenRatiosDriftDown) {
  // The probes' measured ratios at rho = 0.999 drift down slowly (0.99860
  // at four bounces, 0.99853 at sixteen), so partial sum + tail fell with
  // more bounces. Here each ratio is 1e-5 below the one before, from
  // 0.9986, in a scene of albedo 0.999: with MonotoneTailFactor the
  // estimate must not fall from one bounce count to the next, never be
  // below the plain tail, and never exceed the albedo's fixed point
  // d_1 / (1 - 0.999) = 1000 (every ratio and tail is at most 0.999).
  const double rho = 0.999;
  std::vector<double> d = {1.0}, totals = {1.0};
  double r = 0.9986;
  for (int k = 1; k < 32; ++k) {
    d.push_back(d.back() * r);
    totals.push_back(totals.back() + d.back());
    r -= 1e-5;
  }
  double previous = 0.0;
  for (int n = 4; n <= 32; ++n) {
    const std::vector<double> dn(d.begin(), d.begin() + n), tn(totals.begin(), totals.begin() + n);
    const TailEstimate plain = EstimateTail(dn, rho);
    ASSERT_TRUE(plain.applied) << n;
    const double f = MonotoneTailFactor(dn, tn, rho);
    const double estimate = tn.back() + f * dn.back();
    EXPECT_GE(f, plain.ratio / (1.0 - plain.ratio) - 1e-9) << n;
    EXPECT_GE(estimate, previous * (1.0 - 1e-12)) << n << " bounces: not monotone";
    EXPECT_LE(estimate, 1.0 / (1.0 - rho)) << n;
    previous = estimate;
  }
  // No tail at the last bounce: no factor.
  EXPECT_EQ(MonotoneTailFactor({1.0, 0.5, 0.4, 0.2}, {1.0, 1.5, 1.9, 2.1}), 0.0);
}

// TailResidual: the tail-corrected sum's uncertainty from the ratios'
// spread, s r / (1 - r)^2 d_n over S_n + r / (1 - r) d_n; +inf before three
// ratios (five bounces) or without a tail.
TEST(TailEstimate, ResidualIsTheSpreadThroughTheTailFactor) {
  const auto series = [](std::vector<double> ratios) {
    std::vector<double> d = {1.0}, totals = {1.0};
    for (double r : ratios) {
      d.push_back(d.back() * r);
      totals.push_back(totals.back() + d.back());
    }
    return std::pair{d, totals};
  };
  // An exact geometric series: no spread, nothing left to know.
  const auto [d, t] = series({0.9, 0.9, 0.9, 0.9});
  EXPECT_EQ(TailResidual(d, t), 0.0);
  // Four bounces give two ratios: not enough.
  EXPECT_TRUE(std::isinf(TailResidual({d.begin(), d.end() - 1}, {t.begin(), t.end() - 1})));
  // Ratios 0.95, 0.96, 0.97 (3rd bounce on): r = 0.95, spread 0.02 / 0.97.
  const auto [d2, t2] = series({0.5, 0.95, 0.96, 0.97});
  const double r = 0.95, s = 0.02 / 0.97, dn = d2.back();
  const double expected = s * r / ((1 - r) * (1 - r)) * dn / (t2.back() + r / (1 - r) * dn);
  EXPECT_NEAR(TailResidual(d2, t2), expected, 1e-12);
  // An unstable series (no tail): +inf.
  const auto [d3, t3] = series({0.5, 0.9, 0.5, 0.9});
  EXPECT_TRUE(std::isinf(TailResidual(d3, t3)));
}

}  // namespace tail_estimate_test
}  // namespace gistream
