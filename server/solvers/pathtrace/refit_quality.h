// When a refit BVH is still good enough: Embree keeps its node boxes
// private, so the path tracer measures the refit's quality on a shadow
// tree of its own. At build time the deforming triangles are put in the
// Morton order of their centroids (what a spatial build groups together)
// and cut into an implicit 4-ary tree, leaves of 4 triangles; a refit keeps
// that topology and recomputes every box bottom-up, as Embree's refit does
// to its own nodes. The tree's surface-area cost (MacDonald & Booth 1990:
// the expected number of node visits of a random ray, sum of each node's
// area over the root's) at the pose, over the same cost at the build, is
// the growth; above the limit the BVH is rebuilt instead.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace gistream::pathtrace {

class RefitQuality {
 public:
  // A refit whose shadow-tree cost grew beyond this factor rebuilds.
  static constexpr double kMaxCostGrowth = 2.0;

  RefitQuality() = default;
  // Fixes the shadow tree over triangles with these boxes (the built pose).
  explicit RefitQuality(const std::vector<Bounds>& boxes);

  // The shadow tree's cost at the pose with these boxes (same triangles,
  // same order as at construction) over its cost at construction; 1 when
  // there are no triangles.
  double Growth(const std::vector<Bounds>& boxes) const;

 private:
  // Sum over the tree's nodes of area(node) / area(root).
  double Cost(const std::vector<Bounds>& boxes) const;

  std::vector<uint32_t> order_;  // triangle indices in Morton order at construction
  double built_cost_ = 0.0;
};

}  // namespace gistream::pathtrace
