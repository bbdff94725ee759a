#include "solvers/moved_bounds.h"

namespace gistream {

void MovedBounds::Solved(const SceneState& state) {
  solved_ = state.world();
  solved_shapes_.assign(solved_.size(), {});
  for (int n : state.deforming_nodes()) {
    for (const Primitive& p : state.NodeMesh(size_t(n)).primitives) {
      solved_shapes_[size_t(n)].push_back(p.bounds);
    }
  }
}

Bounds MovedBounds::Since(const GpuScene& gpu, const SceneState& state) const {
  Bounds moved;
  const std::vector<glm::mat4>& world = state.world();
  for (const DrawItem& d : gpu.draws()) {
    const size_t node = size_t(d.node);
    const size_t prim = size_t(d.primitive);
    const Bounds& local = state.NodeMesh(node).primitives[prim].bounds;
    if (local.empty()) continue;
    const bool known = node < solved_.size();
    // A deforming node's old box is the one it was solved with.
    const Bounds& old_local =
        known && prim < solved_shapes_[node].size() ? solved_shapes_[node][prim] : local;
    const bool reshaped = old_local.min != local.min || old_local.max != local.max;
    if (known && solved_[node] == world[node] && !reshaped) continue;
    moved.Extend(local.Transformed(world[node]));
    if (known && !old_local.empty()) moved.Extend(old_local.Transformed(solved_[node]));
  }
  return moved;
}

}  // namespace gistream
