// Elements refined near a double-sided emitter (issue 29, item 3; a
// deviation from Dachsbacher et al. 2007, whose meshes come finely
// tessellated). A lamp quad a centimetre under a ceiling lights the
// ceiling above it very brightly, and the light falls off within a few
// centimetres of the lamp's edge. A leaf's radiance is the irradiance at
// its centre (collocation), spread over its cell: a ceiling leaf wider
// than the gap, centred over the lamp, sends the gap's light to the room
// from the part of its cell beyond the lamp's edge too, where the lamp's
// antiradiance does not cancel it (the test's coarse room read 1.21x the
// reference with the near links resolved, 1.00x once the ceiling's edges
// near the lamp were at most 4 x their distance to it). So the edges of
// every other surface near such an emitter are split until each is at
// most kNearFieldEdge x its midpoint's distance to the emitter's box,
// graded outward, never below kNearFieldFloor of the scene-sized limit
// (hierarchy/subdivide.h).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"

namespace gistream::antiradiance {

inline constexpr float kNearFieldEdge = 4.0f;
inline constexpr float kNearFieldFloor = 1.0f / 32.0f;

// A draw of a double-sided emissive material: its world box.
struct NearSheet {
  Bounds box;
  int mesh = -1;
  int primitive = -1;
};
std::vector<NearSheet> DoubleSidedEmitters(const SceneState& state, const GpuScene& gpu);

// The near-field edge test of one (mesh, primitive) drawn with the world
// transforms `world`: the sheets (of other primitives) within reach of
// its instances' boxes, i.e. whose limit there is below the scene-sized
// edge `world_max_edge`, and the instances that have one. Empty (no test)
// when none has.
class NearFieldLimit {
 public:
  NearFieldLimit() = default;
  NearFieldLimit(const std::vector<NearSheet>& sheets, int mesh, int primitive,
                 const Bounds& local_bounds, const std::vector<glm::mat4>& world,
                 float world_max_edge);

  bool empty() const { return sheets_.empty(); }
  // Whether edge (a, b), in the primitive's space, is longer under any
  // near instance than the limit at its midpoint.
  bool TooLong(const glm::vec3& a, const glm::vec3& b) const;
  // For triangle (a, b, c), in the primitive's space: the largest ratio,
  // over the near instances, of its longest edge to the limit at its
  // box's distance from the sheets (how many times its edges may be
  // halved, as a power of two at or above it; memory estimates).
  double SplitRatio(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const;
  // The inputs the test depends on (the sheets' boxes, the near
  // instances' transforms), for a cache of subdivided meshes; empty when
  // the test is.
  std::vector<float> Key() const;

 private:
  std::vector<Bounds> sheets_;
  std::vector<glm::mat4> world_;  // the instances with a sheet in reach
  float world_max_edge_ = 0.0f;
};

// The scene-sized element edge in world units (hierarchy::kMaxElementEdge
// x the scene's diagonal; 0 for an empty or non-finite scene).
float WorldMaxEdge(const SceneState& state, const GpuScene& gpu);

// The world-space edge limit at distance `d` from a sheet.
float NearFieldEdgeAt(float d, float world_max_edge);

// An upper bound on the vertices the near-field test adds to the
// elements of the scene's draws (memory estimate): each triangle near a
// sheet counted as split uniformly to the limit at its box's distance.
uint64_t NearFieldVertexBound(const SceneState& state, const GpuScene& gpu, bool full_detail);

}  // namespace gistream::antiradiance
