#include "solvers/sh_probes/tail_estimate.h"

#include <algorithm>
#include <cmath>

namespace gistream::sh {

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

}  // namespace gistream::sh
