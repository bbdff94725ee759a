// Refinement of the hierarchical links and push-down of their receiving
// ends to the leaves (Dong et al. 2007, Sections 4.2.3-4.2.4; refine_push),
// with each leaf link's weight for the gather (Eq. 5).
#pragma once

#include <cstdint>
#include <vector>

#include "solvers/hierarchy/bin_table.h"
#include "solvers/hierarchy/cube_bins.h"
#include "solvers/hierarchy/elements.h"

namespace gistream::hierarchy {

// The receiving ends of the refined links, pushed down to the leaves, as a
// compressed row per leaf: leaf i gathers sum_k weight[k] * L(source[k]) for
// k in [offset[i], offset[i+1]).
struct LeafLinks {
  std::vector<uint32_t> offset;  // leaf_count + 1
  std::vector<uint32_t> source;  // node ids
  std::vector<float> weight;     // sr: normalized cosine x covered solid angle
  std::vector<uint16_t> bin;     // the receiver's bin the link fills (CubeBins)
  // Open (uncovered) solid angle per bin, for the environment (Section 4.4):
  // leaf i sees the environment in env_bin[k] with weight env_weight[k],
  // k in [env_offset[i], env_offset[i+1]). Empty unless requested.
  std::vector<uint32_t> env_offset;
  std::vector<uint16_t> env_bin;
  std::vector<float> env_weight;

  uint64_t count() const { return source.size(); }
};

struct RefineStats {
  uint64_t leaf_links = 0;    // links gathered by the leaves
  uint64_t blocked_bins = 0;  // bins whose shortest link is a back face (no light, no sky)
  uint64_t empty_bins = 0;    // upper-hemisphere bins without a link
};

// Section 4.2.3 + 4.2.4 in one traversal: in every bin a leaf keeps the
// shortest link among its own and its ancestors' (a shorter link further
// down removes the parent's, which the siblings keep; a longer one is
// removed), then its weight for Eq. 5 is fixed:
//   w = (pi / S(n)) * max(0, n . d_bin) * Omega_bin * min(1, coverage)
// with S(n) = sum_bins Omega max(0, n . d) the discrete cosine integral, so
// a leaf whose upper hemisphere is fully covered gathers exactly
// pi x (average radiance): no energy is created or lost by the bins.
// Multi-threaded over leaves.
LeafLinks RefinePush(const Elements& elements, const CubeBins& bins, const BinTable& table,
                     bool environment, RefineStats* stats);

}  // namespace gistream::hierarchy
