#include "solvers/antiradiance/transport.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "solvers/tail_estimate.h"
#include "util/cancellation.h"
#include "util/parallel_for.h"
#include "util/constants.h"

namespace gistream::antiradiance {
namespace {

double Luminance(const glm::vec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }
bool Finite(const glm::vec3& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}

// Nodes of each root's subtree: [root, next root) in the depth-first layout.
std::vector<std::pair<int, int>> RootRanges(const Patches& p) {
  std::vector<std::pair<int, int>> r;
  for (size_t i = 0; i < p.roots.size(); ++i) {
    r.push_back({p.roots[i], i + 1 < p.roots.size() ? p.roots[i + 1] : p.size()});
  }
  return r;
}

}  // namespace

Transport::Transport(const Patches& patches, const hierarchy::DirectionalBins& bins,
                     std::vector<Link> links)
    : patches_(patches), bins_(bins), links_(std::move(links)), m_(bins.count()) {
  leaves_ = patches_.Leaves();
  const size_t cells = size_t(patches_.size()) * size_t(m_);
  i_ex_.assign(cells, glm::vec3(0.0f));
  l_in_.assign(cells, glm::vec3(0.0f));
  indirect_.assign(size_t(patches_.size()), glm::vec3(0.0f));
  cosine_sum_.resize(leaves_.size());
  for (size_t k = 0; k < leaves_.size(); ++k) {
    const glm::vec3& n = patches_.normal[size_t(leaves_[k])];
    double s = 0.0;
    for (int j = 0; j < m_; ++j) s += std::max(0.0f, glm::dot(n, bins_.direction(j)));
    cosine_sum_[k] = float(s * bins_.omega_bin());
  }
  // Links are sorted by receiver: one range per receiver for the parallel gather.
  for (size_t i = 0; i < links_.size(); ++i) {
    if (i == 0 || links_[i].receiver != links_[i - 1].receiver)
      receiver_begin_.push_back(uint32_t(i));
  }
  receiver_begin_.push_back(uint32_t(links_.size()));
}

void Transport::SetGlossy(const GlossyTransfer* transfer, std::vector<glm::vec3> direct_exitant) {
  glossy_ = transfer;
  const size_t cells = transfer ? size_t(transfer->count()) * size_t(m_) : 0;
  direct_exitant.resize(cells, glm::vec3(0.0f));
  glossy_direct_ = std::move(direct_exitant);
  glossy_source_ = glossy_direct_;
  glossy_out_.assign(cells, glm::vec3(0.0f));
}

void Transport::Initialize(const std::vector<glm::vec3>& direct,
                           const std::vector<glm::vec3>& emitted) {
  source_.assign(leaves_.size(), glm::vec3(0.0f));
  glossy_source_ = glossy_direct_;
  for (size_t k = 0; k < leaves_.size(); ++k) {
    const size_t i = size_t(leaves_[k]);
    const glm::vec3 e_d = i < direct.size() ? direct[i] : glm::vec3(0.0f);
    const glm::vec3 l_e = i < emitted.size() ? emitted[i] : glm::vec3(0.0f);
    source_[k] = patches_.albedo[i] * e_d + kPi * l_e;
    // A glossy leaf's emission leaves every bin alike.
    const int g = glossy_ ? glossy_->slot(int(i)) : -1;
    if (g >= 0 && l_e != glm::vec3(0.0f)) {
      for (int j = 0; j < m_; ++j) {
        if (glm::dot(patches_.normal[i], bins_.direction(j)) > 0.0f)
          glossy_source_[size_t(g) * size_t(m_) + size_t(j)] += l_e;
      }
    }
  }
  radiosity_ = source_;
  std::fill(glossy_out_.begin(), glossy_out_.end(), glm::vec3(0.0f));
  std::fill(l_in_.begin(), l_in_.end(), glm::vec3(0.0f));
  std::fill(indirect_.begin(), indirect_.end(), glm::vec3(0.0f));
  std::fill(i_ex_.begin(), i_ex_.end(), glm::vec3(0.0f));
  LocalPass(/*update_radiance=*/false);  // I_ex = I_L of the source, no antiradiance yet
  Pull();
  step_deltas_.clear();
  step_totals_.clear();
  step_last_ = indirect_;
  step_before_ = indirect_;
  source_norm_ = 0.0;
  for (int leaf : leaves_) {
    for (int j = 0; j < m_; ++j) source_norm_ += std::abs(Luminance(i_ex_[Index(leaf, j)]));
  }
}

void Transport::WarmStart(const Transport& warm) {
  // The source norm (the residual's denominator) stays the sources' own.
  l_in_ = warm.l_in_;
  indirect_ = warm.indirect_;
  for (size_t k = 0; k < leaves_.size(); ++k) {
    const size_t i = size_t(leaves_[k]);
    radiosity_[k] = source_[k] + patches_.albedo[i] * indirect_[i];
    const int g = glossy_ ? glossy_->slot(int(i)) : -1;
    if (g >= 0) glossy_->Reflect(g, &l_in_[Index(int(i), 0)], &glossy_out_[size_t(g) * size_t(m_)]);
  }
  LocalPass(/*update_radiance=*/false);  // I_ex = I_L - I_A of that state
  Pull();
  step_last_ = indirect_;
  step_before_ = indirect_;
}

void Transport::RecordStep() {
  double change = 0.0, total = 0.0;
  for (int i : leaves_) {
    const double e = Luminance(indirect_[size_t(i)]);
    change += std::abs(e - double(Luminance(step_last_[size_t(i)])));
    total += std::abs(e);
  }
  step_deltas_.push_back(change);
  step_totals_.push_back(total);
  step_before_.swap(step_last_);
  step_last_ = indirect_;
}

void Transport::AddTail(double bound, TransportResult* result) {
  // The iterations' increments shrink by r per radiance step once the
  // antiradiance has settled: the steps not run add r / (1 - r) x the
  // last one (geometric tail, MonotoneTailFactor: more steps never give
  // less). Unstable or growing increments (antiradiance still building
  // up, an oscillating symmetric run) give no tail.
  const TailEstimate tail = EstimateTail(step_deltas_, bound);
  if (!tail.applied) return;
  const double f = MonotoneTailFactor(step_deltas_, step_totals_, bound);
  for (int i : leaves_) {
    const glm::dvec3 e(indirect_[size_t(i)]), before(step_before_[size_t(i)]);
    indirect_[size_t(i)] = glm::vec3(glm::max(e + f * (e - before), glm::dvec3(0.0)));
  }
  result->tail_applied = true;
  result->tail_ratio = tail.ratio;
}

void Transport::GlobalPass() {
  // Operator U (Eq. 4) through the links: L_in(x_i, omega_j) += F I_ex(x_k, omega_l)
  // (Eqs. 16-17), spread over the receiver's bins by the cone's table (Section 3.1).
  std::fill(l_in_.begin(), l_in_.end(), glm::vec3(0.0f));
  const size_t receivers = receiver_begin_.size() - 1;
  ParallelFor(receivers, 64, [&](size_t r) {
    for (uint32_t k = receiver_begin_[r]; k < receiver_begin_[r + 1]; ++k) {
      const Link& l = links_[k];
      const glm::vec3 flux = l.form_factor * i_ex_[Index(int(l.sender), l.sender_bin)];
      glm::vec3* dst = &l_in_[Index(int(l.receiver), 0)];
      const auto [begin, end] = bins_.Row(l.cone, l.receiver_bin);
      for (const hierarchy::DirectionalBins::Tap* t = begin; t != end; ++t)
        dst[t->bin] += t->weight * flux;
    }
  });
}

void Transport::Push() {
  // Section 3.2: light gathered at inner nodes goes down to the leaves
  // (radiance, so each child receives its parent's). Parents precede
  // children in the depth-first layout.
  const auto ranges = RootRanges(patches_);
  ParallelFor(ranges.size(), 1, [&](size_t r) {
    for (int i = ranges[r].first; i < ranges[r].second; ++i) {
      if (patches_.is_leaf(i)) continue;
      for (int c : patches_.children[size_t(i)]) {
        if (c < 0) continue;
        for (int j = 0; j < m_; ++j) l_in_[Index(c, j)] += l_in_[Index(i, j)];
      }
    }
  });
}

void Transport::Pull() {
  // Section 3.2: an inner node's intensity is the sum of its children's.
  const auto ranges = RootRanges(patches_);
  ParallelFor(ranges.size(), 1, [&](size_t r) {
    for (int i = ranges[r].second - 1; i >= ranges[r].first; --i) {
      if (patches_.is_leaf(i)) continue;
      glm::vec3* dst = &i_ex_[Index(i, 0)];
      std::fill(dst, dst + m_, glm::vec3(0.0f));
      for (int c : patches_.children[size_t(i)]) {
        if (c < 0) continue;
        const glm::vec3* src = &i_ex_[Index(c, 0)];
        for (int j = 0; j < m_; ++j) dst[j] += src[j];
      }
    }
  });
}

double Transport::LocalPass(bool update_radiance) {
  std::vector<double> change(leaves_.size(), 0.0);
  const float omega = bins_.omega_bin();
  ParallelFor(leaves_.size(), 64, [&](size_t k) {
    const int i = leaves_[k];
    const glm::vec3& n = patches_.normal[size_t(i)];
    const float a = patches_.area[size_t(i)];
    const float s = cosine_sum_[k];
    // Irradiance from the positive hemisphere (the cosine integral of Eq. 18).
    glm::vec3 e(0.0f);
    for (int j = 0; j < m_; ++j) {
      const float c = glm::dot(n, bins_.direction(j));
      if (c > 0.0f) e += (omega * c) * l_in_[Index(i, j)];
    }
    e *= kPi / s;
    indirect_[size_t(i)] = e;
    // K, Eq. 18 for a diffuse BRDF rho / pi: L = B / pi with B = rho (E_d + E).
    if (update_radiance) radiosity_[k] = source_[k] + patches_.albedo[size_t(i)] * e;
    const glm::vec3 b = radiosity_[k] * (a / s);
    // K with the BRDF for a glossy leaf (glossy_transfer.h): L = L_d + T L_in.
    const int g = glossy_ ? glossy_->slot(i) : -1;
    const glm::vec3* l_d = g >= 0 ? &glossy_source_[size_t(g) * size_t(m_)] : nullptr;
    glm::vec3* l_r = g >= 0 ? &glossy_out_[size_t(g) * size_t(m_)] : nullptr;
    if (g >= 0 && update_radiance) glossy_->Reflect(g, &l_in_[Index(i, 0)], l_r);
    double d = 0.0;
    bool finite = true;
    for (int j = 0; j < m_; ++j) {
      const float c = glm::dot(n, bins_.direction(j));
      glm::vec3 v;
      if (c > 0.0f) {
        // I_L(omega_j) = a <n|omega_j> L
        v = g >= 0 ? (a * c) * (l_d[j] + l_r[j]) : c * b;
      } else {
        // J, Eq. 19: light incident from -omega_j leaves towards omega_j as
        // antiradiance, I_A = a <n|-omega_j> L_in, stored negated in I_ex.
        v = (a * c) * l_in_[Index(i, bins_.opposite(j))];
      }
      glm::vec3& slot = i_ex_[Index(i, j)];
      d += std::abs(Luminance(v - slot));
      finite = finite && Finite(v);
      slot = v;
    }
    change[k] = finite && Finite(e) ? d : std::nan("");
  });
  return std::accumulate(change.begin(), change.end(), 0.0);
}

double Transport::RunScheme(Scheme scheme, const TransportSettings& s, const StageHook& hook,
                            TransportResult* result, bool watch_divergence) {
  auto stage = [&](const char* name, bool begin) {
    if (hook) hook(name, begin);
  };
  auto step = [&](bool radiance) {
    // A cancelled job (util/cancellation.h) ends here: what it leaves is
    // discarded (solvers/background_job.h).
    if (Cancelled()) return std::nan("");
    stage("global_pass", true);
    GlobalPass();
    stage("global_pass", false);
    stage("push_pull", true);
    Push();
    stage("push_pull", false);
    stage("local_pass", true);
    const double d = LocalPass(radiance);
    stage("local_pass", false);
    stage("push_pull", true);
    Pull();
    stage("push_pull", false);
    if (radiance) RecordStep();
    ++result->global_passes;
    const double r = source_norm_ > 0.0 ? d / source_norm_ : d;
    result->residual.push_back(r);
    return r;
  };
  result->iterations = 0;
  for (int it = 0; it < s.iterations; ++it) {
    result->iterations = it + 1;
    if (scheme == Scheme::kAsymmetric) {
      // Eq. 14 with L^(i) frozen, then one step of Eq. 13.
      // The antiradiance steps run until A stops changing (at most
      // antiradiance_steps, which must cover the scene's depth complexity).
      for (int a = 0; a < s.antiradiance_steps; ++a) {
        const double r = step(false);
        if (!std::isfinite(r)) return std::nan("");
        if (r < s.antiradiance_tolerance) break;
      }
      const double r = step(true);
      if (!std::isfinite(r)) return std::nan("");
      if (r < s.tolerance) return r;  // converged
      continue;
    }
    // Symmetric: Eqs. 13 and 14 together.
    const double r = step(true);
    if (!std::isfinite(r)) return std::nan("");
    const auto& h = result->residual;
    if (watch_divergence && h.size() >= 3 && h[h.size() - 1] > h[h.size() - 2] &&
        h[h.size() - 2] > h[h.size() - 3]) {
      return std::nan("");  // grew two iterations in a row
    }
    if (r < s.tolerance) return r;  // converged
  }
  result->cap_reached = true;  // every iteration ran without reaching the tolerance
  return result->residual.empty() ? 0.0 : result->residual.back();
}

TransportResult Transport::Solve(const std::vector<glm::vec3>& direct_irradiance,
                                 const std::vector<glm::vec3>& emitted,
                                 const TransportSettings& settings, const StageHook& hook,
                                 const Transport* warm) {
  TransportResult result;
  result.scheme_used = settings.scheme;
  Initialize(direct_irradiance, emitted);
  if (warm != nullptr && warm->leaves_ == leaves_ && warm->l_in_.size() == l_in_.size()) {
    WarmStart(*warm);
  }
  double r = RunScheme(settings.scheme, settings, hook, &result,
                       /*watch_divergence=*/settings.scheme == Scheme::kSymmetric);
  if (!std::isfinite(r) && settings.scheme == Scheme::kSymmetric) {
    // Stability fallback: the asymmetric scheme provably converges (Section 2.2).
    result.fallback = true;
    result.scheme_used = Scheme::kAsymmetric;
    result.symmetric_residual = std::move(result.residual);
    result.residual.clear();
    result.cap_reached = false;
    Initialize(direct_irradiance, emitted);
    r = RunScheme(Scheme::kAsymmetric, settings, hook, &result, false);
  }
  if (!std::isfinite(r)) {
    result.non_finite = true;
    std::fill(indirect_.begin(), indirect_.end(), glm::vec3(0.0f));
  } else if (settings.tail_bound > 0.0) {
    AddTail(settings.tail_bound, &result);
  }
  return result;
}

}  // namespace gistream::antiradiance
