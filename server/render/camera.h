// A session's view: pose, vertical field of view and image size.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene/state/scene_state.h"
#include "scene/updates.h"

namespace gistream {

struct ViewCamera {
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // looks down -Z
  float yfov = 0.8f;                           // radians
  uint32_t width = 64;
  uint32_t height = 64;
  // Clip planes; set per frame by WithDepthRange (zfar 0: infinite).
  float znear = 0.01f;
  float zfar = 0.0f;
  // The scene camera node the pose came from (its glTF znear/zfar apply);
  // -1 once a client set the pose (look_at, pose).
  int scene_camera_node = -1;
  // Sub-pixel offset of the film, in pixels (each in [-0.5, 0.5); 0: pixel
  // centres). A still view's refinement shifts it per sample
  // (render/refinement.h); Projection() applies it, RayDirection does not.
  glm::vec2 jitter{0.0f};

  glm::mat4 View() const;
  // perspective(znear, zfar), infinite when zfar = 0; then shifted by
  // `jitter` pixels in NDC.
  glm::mat4 Projection() const;
  // Unit world direction through the film point ndc in [-1, 1]^2 (x right,
  // y up), from the camera's basis and tan(yfov / 2): no matrix inversion,
  // so exact at any scene scale.
  glm::vec3 RayDirection(glm::vec2 ndc) const;
};

// Scene camera 0 when the scene has one, else a view of the bounds from +Z.
ViewCamera DefaultCamera(const SceneState& state, uint32_t width, uint32_t height);

// `camera` with znear/zfar for this frame, from the glTF camera (when the
// view is a scene camera's; znear/zfar scaled with the node's world scale)
// and the current geometry's box `world_bounds`. Far: the glTF zfar, else
// just beyond the box's farthest corner. Near: when a lower bound on the
// view depth of everything in the box and frustum is known (the whole box
// in front: its nearest corner's depth; camera outside: its distance x the
// cosine of the frustum's diagonal half-angle), the larger of 0.99 x that
// and the glTF znear: it clips nothing the author did not. Otherwise (the
// camera inside the box, part of it behind) the glTF znear, else 1e-3 of
// the diagonal, at most max(half the distance to the nearest face, 1e-3 of
// the diagonal). Depth precision then follows the scene's proportions, not
// its absolute size (micrometres to 1000 km).
ViewCamera WithDepthRange(ViewCamera camera, const SceneState& state, const Bounds& world_bounds);

// Applies a validated camera update. Returns true when the size changed.
bool ApplyCameraUpdate(const SceneState& state, const CameraUpdate& update, ViewCamera& camera);

}  // namespace gistream
