#include "solvers/moved_bounds.h"

namespace gistream {
namespace {

Bounds Transformed(const Bounds& local, const glm::mat4& m) {
  Bounds world;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? local.max.x : local.min.x,
                      (corner & 2) ? local.max.y : local.min.y,
                      (corner & 4) ? local.max.z : local.min.z);
    world.Extend(glm::vec3(m * glm::vec4(p, 1.0f)));
  }
  return world;
}

}  // namespace

Bounds MovedBounds::Since(const GpuScene& gpu, const SceneState& state) const {
  Bounds moved;
  const std::vector<glm::mat4>& world = state.world();
  for (const DrawItem& d : gpu.draws()) {
    const Bounds& local =
        state.scene().meshes[size_t(d.mesh)].primitives[size_t(d.primitive)].bounds;
    if (local.empty()) continue;
    const size_t node = size_t(d.node);
    const bool known = node < solved_.size();
    if (known && solved_[node] == world[node]) continue;
    moved.Extend(Transformed(local, world[node]));
    if (known) moved.Extend(Transformed(local, solved_[node]));
  }
  return moved;
}

}  // namespace gistream
