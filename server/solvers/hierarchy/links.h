// Hierarchical link creation with implicit visibility (Dong et al. 2007,
// Section 4.2.2; create_links). Refinement and push-down are in
// refine_push.h.
#pragma once

#include <cstdint>
#include <vector>

#include "solvers/hierarchy/bin_table.h"
#include "solvers/hierarchy/cube_bins.h"
#include "solvers/hierarchy/elements.h"

namespace gistream::hierarchy {

enum class Linking {
  kHierarchical,  // Section 4.2.2: all top-level nodes, subdividing by solid angle
  kBruteForce,    // Section 3.1: every pair of leaves (the paper's Fig. 10b)
};

struct LinkStats {
  uint64_t offered = 0;     // links offered to bins (each stored in two bins)
  uint64_t node_pairs = 0;  // Link(A, B) calls, subdivisions included
  uint64_t stored = 0;      // non-empty bins after linking
  uint64_t splats = 0;      // receiving ends spread over several bins (a leaf larger than a bin)
};

// Offers every link of the forest to `table` (reset to elements x bins).
// Multi-threaded over pairs of top-level nodes.
LinkStats CreateLinks(const Elements& elements, const CubeBins& bins, Linking linking,
                      BinTable& table);

}  // namespace gistream::hierarchy
