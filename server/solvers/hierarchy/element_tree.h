// The geometric hierarchy of one mesh primitive (Dong et al. 2007, Section
// 4.1; create_hierarchy): a forest of trees of up to four children per
// node over the primitive's surfels, computed once and reused every frame.
//
// The paper takes the artist's UV charts as the coarsest clusters. Our
// scenes often have none, so charts are made from position and normal:
// surfels are grouped by the dominant axis of their normal (six groups,
// each within ~55 degrees of a cube axis), and each chart is split
// recursively, two median cuts per level, along the widest dimension of
// (position, 0.3 x cluster size x normal), so children are adjacent and
// similarly oriented.
//
// Node numbering is pointer-less as in Section 4.3.1: leaves are the
// surfels, 0..leaf_count-1 in vertex order; internal nodes follow, sorted
// by height (leaves height 0), so a bottom-up pass is a walk in index order.
#pragma once

#include <array>
#include <vector>

#include "solvers/hierarchy/surfels.h"

namespace gistream::hierarchy {

struct ElementTree {
  struct Internal {
    std::array<int, 4> children{-1, -1, -1, -1};  // node ids, -1 unused
    int height = 1;
  };

  int leaf_count = 0;
  std::vector<Internal> internal;  // node leaf_count + i
  std::vector<int> parent;         // per node; -1 for a root
  std::vector<int> roots;          // one per chart

  int node_count() const { return leaf_count + int(internal.size()); }
  int height(int node) const {
    return node < leaf_count ? 0 : internal[size_t(node - leaf_count)].height;
  }
};

ElementTree CreateHierarchy(const Surfels& surfels);

}  // namespace gistream::hierarchy
