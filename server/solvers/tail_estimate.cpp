#include "solvers/tail_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "solvers/brdf_albedo.h"

namespace gistream {

TailEstimate EstimateTail(const std::vector<double>& deltas, double albedo_bound) {
  TailEstimate t;
  const int n = int(deltas.size());
  // Ratios r_k = d_k / d_{k-1} for bounces k >= 3 (indices k - 1 >= 2),
  // the last three at most.
  const int first = std::max(2, n - 3);
  double lo = 0.0, hi = 0.0;
  for (int k = first; k < n; ++k) {
    const double prev = deltas[size_t(k - 1)], cur = deltas[size_t(k)];
    if (!(prev > 0.0) || !std::isfinite(prev) || !std::isfinite(cur)) return t;
    const double r = cur / prev;
    if (!(r > 0.0) || !(r < 1.0)) return t;  // not a converging series
    lo = t.ratios == 0 ? r : std::min(lo, r);
    hi = t.ratios == 0 ? r : std::max(hi, r);
    ++t.ratios;
  }
  if (t.ratios < 2) return t;
  t.spread = (hi - lo) / hi;
  t.ratio = std::min({lo, albedo_bound, kMaxTailRatio});
  t.applied = t.spread <= kTailStability;
  if (!t.applied) t.ratio = 0.0;
  return t;
}

double TailResidual(const std::vector<double>& deltas, const std::vector<double>& totals,
                    double albedo_bound) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  const size_t n = std::min(deltas.size(), totals.size());
  if (n == 0) return kNone;
  const TailEstimate t = EstimateTail({deltas.begin(), deltas.begin() + long(n)}, albedo_bound);
  if (!t.applied || t.ratios < 3) return kNone;
  const double r = t.ratio, d = deltas[n - 1];
  const double estimate = totals[n - 1] + r / (1.0 - r) * d;
  if (!(estimate > 0.0) || !std::isfinite(estimate) || !(d >= 0.0)) return kNone;
  const double residual = t.spread * r / ((1.0 - r) * (1.0 - r)) * d / estimate;
  return std::isfinite(residual) ? residual : kNone;
}

double MonotoneTailFactor(const std::vector<double>& deltas, const std::vector<double>& totals,
                          double albedo_bound) {
  const size_t n = std::min(deltas.size(), totals.size());
  if (n == 0) return 0.0;
  const TailEstimate last = EstimateTail({deltas.begin(), deltas.begin() + long(n)}, albedo_bound);
  if (!last.applied) return 0.0;
  const double f_last = last.ratio / (1.0 - last.ratio);
  const double d_last = deltas[n - 1];
  if (!(d_last > 0.0) || !std::isfinite(totals[n - 1])) return f_last;
  double best = totals[n - 1] + f_last * d_last;
  for (size_t k = 0; k + 1 < n; ++k) {
    const TailEstimate t =
        EstimateTail({deltas.begin(), deltas.begin() + long(k + 1)}, albedo_bound);
    if (!t.applied) continue;
    const double estimate = totals[k] + t.ratio / (1.0 - t.ratio) * deltas[k];
    if (std::isfinite(estimate)) best = std::max(best, estimate);
  }
  return std::max(f_last, (best - totals[n - 1]) / d_last);
}

double LargestAlbedo(const SceneState& state) {
  double bound = 0.0;
  for (const Material& m : state.materials()) {
    const glm::vec3 c = glm::clamp(glm::vec3(m.base_color_factor), 0.0f, 1.0f);
    // A glossy material's transport albedo (white-sky, brdf_albedo.h) can
    // pass its base colour in a dark channel (a metal's B adds to F0).
    const glm::vec3 w = BrdfWhiteSkyAlbedo(c, std::clamp(m.metallic_factor, 0.0f, 1.0f),
                                           std::clamp(m.roughness_factor, 0.0f, 1.0f),
                                           m.specular_f0, m.specular_f90);
    bound = std::max(bound, double(std::max({c.r, c.g, c.b, w.r, w.g, w.b})));
  }
  return bound;
}

}  // namespace gistream
