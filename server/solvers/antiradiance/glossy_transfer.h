// The local pass's BRDF for glossy leaves (Dachsbacher et al. 2007,
// Section 3.1's local pass K with a general BRDF, as their glossy box and
// bust use a Lafortune BRDF, Fig. 15): a leaf's exitant radiance in bin
// omega_o is the sum over the incident bins omega_j of
//   L(omega_o) = sum_j f(omega_j, omega_o) <n|omega_j>_+ omega_bin L_in(omega_j)
// with brdf.glsl's GGX (solvers/shading/ggx.h). Per (material, normal)
// this is a bin-to-bin matrix T over the leaf's upper hemisphere of bins
// (the bins are world-space, so two leaves share T only when their normals
// are equal, e.g. the faces of a box).
//
// T's entries: the BRDF averaged over seven directions of a bin (its
// centre and six at half its radius), at one end and then the other
// (symmetric, as f is reciprocal), with the roughness raised to
// the bins' ResolvedRoughness (a lobe narrower than the bins would fall
// between them; sharper materials are blurred to that lobe). The symmetric kernel K is
// then scaled as D K D (Sinkhorn-Knopp) so that every row and column
// reflects the true material's directional albedo (brdf_albedo.h):
//   sum_j K'[o][j] <n|omega_j>_+ omega_bin = albedo(omega_o),
//   T[o][j] = K'[o][j] <n|omega_j>_+ omega_bin pi / S(n)
// with the diffuse pass's cosine correction pi / S(n) (transport.h). In a
// white furnace each bin then reflects its directional albedo and each
// incident bin sends out that albedo of its flux, never more; a Lambertian
// BRDF gives the diffuse local pass's L = B / S(n).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "absl/status/statusor.h"
#include "solvers/hierarchy/directional_bins.h"
#include "solvers/antiradiance/patches.h"
#include "solvers/shading/ggx.h"

namespace gistream::antiradiance {

class GlossyTransfer {
 public:
  // The slot of each node (-1: a Lambertian leaf, or not a leaf), from the
  // leaves' BRDFs (`brdf` per node; every non-Lambertian leaf is glossy).
  static std::vector<int> Slots(const Patches& patches, const std::vector<shading::Brdf>& brdf);
  // The matrices of every glossy leaf; ResourceExhausted (naming
  // params.bins) beyond `max_bytes`.
  static absl::StatusOr<GlossyTransfer> Build(const Patches& patches,
                                              const hierarchy::DirectionalBins& bins,
                                              const std::vector<shading::Brdf>& brdf,
                                              uint64_t max_bytes);
  int count() const { return int(matrix_of_slot_.size()); }
  int slot(int node) const { return slot_.empty() ? -1 : slot_[size_t(node)]; }
  int matrices() const { return int(matrices_.size()); }
  // out[o] = sum_j T[o][j] l_in[j] over glossy slot `s`'s hemisphere; out
  // (m entries) is zero below it.
  void Reflect(int s, const glm::vec3* l_in, glm::vec3* out) const;
  uint64_t bytes() const;

 private:
  struct Matrix {
    std::vector<uint16_t> hemisphere;  // bins with <n|omega> > 0
    std::vector<glm::vec3> t;          // [o * h + j], h = hemisphere.size()
  };
  // Build's steps for one (material, normal): the hemisphere's bins and
  // the transfer matrix T (BlurredKernel's K scaled to the BRDF's albedo).
  static Matrix BuildMatrix(const hierarchy::DirectionalBins& bins, const glm::vec3& n,
                            const shading::Brdf& material, float min_roughness);
  // kSubSamples directions per hemisphere bin (its centre first), in the
  // frame of `n`.
  static std::vector<glm::vec3> SubSampleDirections(const hierarchy::DirectionalBins& bins,
                                                    const glm::vec3& n,
                                                    const std::vector<uint16_t>& hemisphere);
  // The blurred BRDF between the h bins, averaged over sub-samples and
  // symmetrized.
  static std::vector<glm::vec3> BlurredKernel(const shading::Brdf& blurred,
                                              const std::vector<glm::vec3>& wo, size_t h);

  int m_ = 0;
  std::vector<int> slot_;                 // per node
  std::vector<uint32_t> matrix_of_slot_;  // per slot
  std::vector<Matrix> matrices_;
};

}  // namespace gistream::antiradiance
