// A session's view: pose, vertical field of view and image size.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene/scene_state.h"
#include "scene/updates.h"

namespace gistream {

struct ViewCamera {
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // looks down -Z
  float yfov = 0.8f;                           // radians
  uint32_t width = 64;
  uint32_t height = 64;
  float znear = 0.01f;

  glm::mat4 View() const;
  glm::mat4 Projection() const;  // infinite far plane
};

// Scene camera 0 when the scene has one, else a view of the bounds from +Z.
ViewCamera DefaultCamera(const SceneState& state, uint32_t width, uint32_t height);

// Applies a validated camera update. Returns true when the size changed.
bool ApplyCameraUpdate(const SceneState& state, const CameraUpdate& update, ViewCamera& camera);

}  // namespace gistream
