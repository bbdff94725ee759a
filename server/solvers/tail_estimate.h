// The geometric tail of an iterative solver's bounce series (the bounces
// not run), estimated only from what the measured bounces support: the
// iterative GI solvers (sh_probes, implicit_visibility, antiradiance) add
// it to what their bounces gathered (issue 29, item 4: a stiff scene
// converges at the defaults instead of stopping at the bounce cap).
#pragma once

#include <vector>

#include "scene/state/scene_state.h"

namespace gistream {

struct TailEstimate {
  bool applied = false;
  double ratio = 0.0;   // r used: the tail adds r / (1 - r) x the last increment
  double spread = 0.0;  // (max - min) / max of the ratios considered
  int ratios = 0;       // how many ratios were considered
};

// The most a ratio may imply whatever the scene: r / (1 - r) = 9999 x the
// last increment (float sums carry no more digits).
inline constexpr double kMaxTailRatio = 0.9999;
// Ratios that differ by more than this fraction are not a geometric series
// (yet): no tail.
inline constexpr double kTailStability = 0.05;

// `deltas[k]` is the change that bounce k + 1 made (deltas[0]: the first,
// direct-lit bounce). Ratios r_k = d_k / d_{k-1} are taken from the third
// bounce on (the first indirect bounce redistributes light differently
// from the direct one), the last three at most; the tail needs at least two
// of them, each finite in (0, 1), within kTailStability of each other. It
// uses the smallest (the series' ratio is never taken above any measured
// one), capped at `albedo_bound` and kMaxTailRatio. Otherwise no tail
// (applied = false).
//
// albedo_bound: the scene's largest albedo. Each bounce multiplies the
// light by the albedo and by form factors whose rows sum to at most 1
// (closed scene: exactly 1), so the increments' ratio never exceeds it;
// a measured ratio above it is rounding (the probes' half-float albedo,
// float sums), and taking it would overshoot by r / (1 - r).
TailEstimate EstimateTail(const std::vector<double>& deltas, double albedo_bound = kMaxTailRatio);

// The factor f by which the last increment is scaled so that running more
// bounces never lowers the estimate (issue 14: at rho = 0.999 the measured
// ratios drift down slightly from bounce to bounce, and the partial sum
// plus its tail fell by 0.3 % from 4 to 16 bounces). `totals[k]` is the
// solution's sum after bounce k + 1. Each bounce n at which a tail applies
// gives T_n = totals[n] + f_n deltas[n], f_n = r_n / (1 - r_n) from
// EstimateTail over the first n + 1 bounces. While the measured ratios
// are at most albedo_bound (r_n always is), every T_n is at most the
// bound's fixed point d_1 / (1 - albedo_bound), so their largest is too;
// a later T_n is lower only because its measured ratio is (rounding in
// the probes' sums, not the scene). Returns (max_n T_n - totals[last]) /
// deltas[last], never below the last f_n; 0 when no tail applies at the
// last bounce.
double MonotoneTailFactor(const std::vector<double>& deltas, const std::vector<double>& totals,
                          double albedo_bound = kMaxTailRatio);

// How far the tail-corrected estimate S_n + f d_n (f = r / (1 - r), r from
// EstimateTail over all of `deltas`) may still be from the series' sum,
// relative to it: a ratio known to within its measured spread s (r lies in
// [r (1 - s), r]) moves f by up to s r / (1 - r)^2, so the tail by that
// times d_n. An iterative solver may stop once this is small against its
// tolerance (TailSettled, below): the bounces it would still run mostly
// confirm the tail (sh_probes, implicit_visibility). Needs three stable
// ratios (five bounces: the ratios from the third on); else +infinity. `totals[k]`: the sum after
// bounce k + 1.
double TailResidual(const std::vector<double>& deltas, const std::vector<double>& totals,
                    double albedo_bound = kMaxTailRatio);

// Whether a solve may end on its tail: TailResidual below a tenth of the
// tolerance. The residual is the aggregate's (sums over the whole scene);
// a dark corner lit only by late bounces converges more slowly than the
// sum, and at the tolerance itself the Cornell box's shadowed corner came
// out 7 % below the converged picture (implicit_visibility, 6 bounces, where
// the increment test's 8 left 1.7 %).
inline constexpr double kTailStopFraction = 0.1;
inline bool TailSettled(double tail_residual, double tolerance) {
  return tail_residual < kTailStopFraction * tolerance;
}

// The scene's largest albedo (base colour factors and, for glossy
// materials, their white-sky albedo; textures only scale them down): the
// bound on a closed scene's bounce ratio.
double LargestAlbedo(const SceneState& state);

}  // namespace gistream
