// The iterative solution of Dachsbacher et al. 2007 on the element
// hierarchy (Sections 2.2, 3.1, 3.2): per node and bin the exitant
// intensity I_ex = I_L - I_A and the incident radiance L_in, and the four
// operations of one iteration:
//   global_pass  L_in = U I_ex along the links (Eqs. 16-17, spreading tables)
//   push_pull    push L_in down to the leaves / pull I_ex up (sum of children)
//   local_pass   K (Eq. 18, diffuse) and J (Eq. 19) at the leaves
// in the symmetric scheme (alternate Eqs. 13 and 14) or the asymmetric one
// (after each radiance step, antiradiance steps with L frozen). A residual
// is tracked per iteration; a symmetric frame whose residual grows two
// iterations in a row, or turns non-finite, is redone asymmetrically.
//
// A diffuse leaf's I_L is a_i <n_i|omega_j>_+ B_i / S(n_i) with B_i its
// exitant radiosity and S(n) = sum_j omega_bin <n|omega_j>_+ the discrete
// cosine integral (~pi): the bins then carry exactly a_i B_i of flux. A
// glossy leaf (SetGlossy) carries a_i <n_i|omega_j>_+ (L_d(omega_j) +
// (T L_in)(omega_j)): its direct light's exitant radiance per bin plus K
// with the BRDF, the bin-to-bin matrix T of glossy_transfer.h.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/hierarchy/directional_bins.h"
#include "solvers/antiradiance/glossy_transfer.h"
#include "solvers/antiradiance/links.h"
#include "solvers/antiradiance/patches.h"

namespace gistream::antiradiance {

enum class Scheme { kSymmetric = 0, kAsymmetric = 1 };

struct TransportSettings {
  int iterations = 4;  // most iterations (symmetric) or radiance steps (asymmetric)
  // Stop once an iteration's (radiance step's) residual is below this; 0:
  // run every iteration. The count above is then only a safety cap.
  double tolerance = 0.0;
  Scheme scheme = Scheme::kSymmetric;
  int antiradiance_steps = 16;           // asymmetric: most Eq. 14 steps per radiance step
  double antiradiance_tolerance = 1e-3;  // asymmetric: stop Eq. 14 below this residual
  // > 0: add the geometric tail of the iterations not run to the leaves'
  // indirect irradiance (solvers/tail_estimate.h), its ratio at most this
  // (the scene's largest albedo); 0: none.
  double tail_bound = 0.0;
};

struct TransportResult {
  Scheme scheme_used = Scheme::kSymmetric;
  bool fallback = false;    // symmetric diverged; redone asymmetrically
  bool non_finite = false;  // even the asymmetric scheme produced NaN/Inf (output zeroed)
  int global_passes = 0;
  int iterations = 0;            // iterations (radiance steps) of the scheme used
  bool cap_reached = false;      // stopped by `iterations` with residual >= tolerance
  std::vector<double> residual;  // per global pass of the scheme used: |dI_ex|_1 / |I_ex^(0)|_1
  std::vector<double> symmetric_residual;  // the abandoned symmetric run, when fallback
  bool tail_applied = false;               // the iterations not run were added
  double tail_ratio = 0.0;                 // their ratio r (0: no tail)
};

// Stage hooks so the caller can time the passes (gl::StageTimer).
using StageHook = std::function<void(const char* stage, bool begin)>;

class Transport {
 public:
  Transport(const Patches& patches, const hierarchy::DirectionalBins& bins,
            std::vector<Link> links);

  // Sources per node (leaves used): direct irradiance E_d (W/m^2, from the
  // shadow maps, Section 3.3, no antiradiance) and emitted radiance L_e
  // (nits) to transport (the solver leaves L_e to the direct term).
  // `warm`: a solution of the same elements (same nodes and leaves; other
  // positions, links or sources) to iterate from instead of from the
  // sources alone (Section 3.3: "we iterate from the previous solution");
  // ignored when its layout differs. The asymmetric fallback after a
  // divergence starts from the sources, as without it.
  // Glossy leaves (before Solve; none by default): `transfer` (kept by the
  // caller) and per glossy slot the direct light's exitant radiance per bin,
  // direct_exitant[slot * m + j] (zero below the surface; missing: zero).
  void SetGlossy(const GlossyTransfer* transfer, std::vector<glm::vec3> direct_exitant);

  TransportResult Solve(const std::vector<glm::vec3>& direct_irradiance,
                        const std::vector<glm::vec3>& emitted, const TransportSettings& settings,
                        const StageHook& hook = {}, const Transport* warm = nullptr);

  // After Solve, per node (leaves): indirect irradiance
  // E = (pi / S(n)) sum_j omega_bin <n|omega_j>_+ L_in(j) of the last pass,
  // plus the tail when settings.tail_bound asks for it.
  const std::vector<glm::vec3>& indirect_irradiance() const { return indirect_; }
  const glm::vec3& L_in(int node, int bin) const { return l_in_[Index(node, bin)]; }
  // After Solve, glossy slot s's reflected indirect radiance T L_in per bin
  // (m entries, zero below the surface): what the display looks up.
  const glm::vec3* glossy_indirect(int s) const { return &glossy_out_[size_t(s) * size_t(m_)]; }
  const GlossyTransfer* glossy() const { return glossy_; }
  const glm::vec3& I_ex(int node, int bin) const { return i_ex_[Index(node, bin)]; }
  const std::vector<Link>& links() const { return links_; }
  uint64_t table_bytes() const { return (i_ex_.size() + l_in_.size()) * sizeof(glm::vec3); }
  uint64_t link_bytes() const { return links_.size() * sizeof(Link) + receiver_begin_.size() * 4; }

 private:
  size_t Index(int node, int bin) const { return size_t(node) * size_t(m_) + size_t(bin); }
  void Initialize(const std::vector<glm::vec3>& direct, const std::vector<glm::vec3>& emitted);
  // After Initialize: start from `warm`'s incident radiance and indirect
  // irradiance (the radiosity is this source plus albedo x that irradiance).
  void WarmStart(const Transport& warm);
  void GlobalPass();
  void Push();
  // K (when update_radiance) and J at the leaves; returns |dI_ex|_1 or NaN.
  double LocalPass(bool update_radiance);
  void Pull();
  double RunScheme(Scheme scheme, const TransportSettings& s, const StageHook& hook,
                   TransportResult* result, bool watch_divergence);
  // After a radiance step: its change of the leaves' indirect irradiance.
  void RecordStep();
  // E += f (E - E of the step before) at the leaves (solvers/tail_estimate.h).
  void AddTail(double bound, TransportResult* result);

  const Patches& patches_;
  const hierarchy::DirectionalBins& bins_;
  std::vector<Link> links_;
  std::vector<uint32_t> receiver_begin_;  // link ranges with one receiver
  int m_;
  std::vector<int> leaves_;
  std::vector<float> cosine_sum_;     // S(n) per leaf slot
  std::vector<glm::vec3> source_;     // rho E_d + pi L_e per leaf slot (radiosity of the source)
  std::vector<glm::vec3> radiosity_;  // B per leaf slot
  std::vector<glm::vec3> indirect_;   // per node
  std::vector<glm::vec3> i_ex_, l_in_;
  const GlossyTransfer* glossy_ = nullptr;
  std::vector<glm::vec3> glossy_direct_;  // per glossy slot x bin: the direct light's L_d
  std::vector<glm::vec3> glossy_source_;  // L_d + L_e
  std::vector<glm::vec3> glossy_out_;     // per glossy slot x bin: T L_in
  double source_norm_ = 0.0;
  // Per radiance step: sum |dE|, sum |E| over the leaves (luminance), and
  // the leaves' E after the step before the last (the tail's increment).
  std::vector<double> step_deltas_, step_totals_;
  std::vector<glm::vec3> step_before_, step_last_;
};

}  // namespace gistream::antiradiance
