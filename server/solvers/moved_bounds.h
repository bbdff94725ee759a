// What moved since a solve: the solver remembers the world transforms it
// solved for, and after a geometry change asks for the box around every
// drawn primitive whose node moved, old and new place together. Progressive
// solvers use it to update what the change affects first.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"

namespace gistream {

class MovedBounds {
 public:
  // The current transforms (and deformed shapes) are the solved ones.
  void Solved(const SceneState& state);
  // The union of the old and new world boxes (8 transformed corners, as
  // GpuScene::WorldBounds) of every drawn primitive whose node's world
  // transform differs from the solved one, or whose deformed mesh
  // (SceneState::NodeMesh) changed its box; empty when none does. Every
  // primitive counts as moved before the first Solved.
  Bounds Since(const GpuScene& gpu, const SceneState& state) const;

 private:
  std::vector<glm::mat4> solved_;
  // Per node: the local primitive boxes of a deforming node's posed mesh.
  std::vector<std::vector<Bounds>> solved_shapes_;
};

}  // namespace gistream
