#include "render/camera.h"

#include <algorithm>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/matrix_decompose.hpp>

namespace gistream {
namespace {

// Near plane scaled to the scene so millimetre and kilometre scenes both
// keep depth precision.
float NearPlane(const SceneState& state) {
  const float size = glm::length(state.scene().bounds.extent());
  return std::clamp(size * 1e-4f, 1e-6f, 1.0f);
}

void FromSceneCamera(const SceneState& state, int node, ViewCamera& camera) {
  const Scene& scene = state.scene();
  glm::vec3 scale, translation, skew;
  glm::vec4 perspective;
  glm::quat rotation;
  glm::decompose(state.world()[size_t(node)], scale, rotation, translation, skew, perspective);
  camera.position = translation;
  camera.rotation = glm::normalize(rotation);
  camera.yfov = scene.cameras[size_t(scene.nodes[size_t(node)].camera)].yfov;
}

}  // namespace

glm::mat4 ViewCamera::View() const {
  return glm::inverse(glm::translate(glm::mat4(1.0f), position) * glm::mat4_cast(rotation));
}

glm::mat4 ViewCamera::Projection() const {
  const float aspect = float(width) / float(std::max<uint32_t>(height, 1));
  return glm::infinitePerspective(yfov, aspect, znear);
}

ViewCamera DefaultCamera(const SceneState& state, uint32_t width, uint32_t height) {
  ViewCamera camera;
  camera.width = width;
  camera.height = height;
  camera.znear = NearPlane(state);
  const std::vector<int> cameras = CameraInstanceNodes(state.scene());
  if (!cameras.empty()) {
    FromSceneCamera(state, cameras.front(), camera);
    return camera;
  }
  const Bounds& b = state.scene().bounds;
  const glm::vec3 center = b.empty() ? glm::vec3(0.0f) : b.center();
  const float radius = b.empty() ? 1.0f : std::max(0.5f * glm::length(b.extent()), 1e-6f);
  const float distance = radius / std::tan(0.5f * camera.yfov) * 1.1f;
  camera.position = center + glm::vec3(0.0f, 0.0f, distance);
  return camera;
}

bool ApplyCameraUpdate(const SceneState& state, const CameraUpdate& update, ViewCamera& camera) {
  if (update.look_at) {
    const LookAt& l = *update.look_at;
    glm::vec3 up = glm::length(l.up) > 0.0f ? glm::normalize(l.up) : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 forward = glm::normalize(l.target - l.eye);
    if (std::abs(glm::dot(forward, up)) > 0.9999f) {
      up = std::abs(forward.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
    }
    camera.position = l.eye;
    // The inverse of a look-at view matrix is the camera's world rotation.
    camera.rotation = glm::normalize(glm::quat_cast(glm::inverse(glm::lookAt(l.eye, l.target, up))));
  } else if (update.pose) {
    camera.position = update.pose->position;
    camera.rotation = glm::normalize(update.pose->rotation);
  } else if (update.scene_camera) {
    FromSceneCamera(state, CameraInstanceNodes(state.scene())[*update.scene_camera], camera);
  }
  if (update.yfov_degrees) camera.yfov = glm::radians(*update.yfov_degrees);
  bool resized = false;
  if (update.width && update.height) {
    resized = *update.width != camera.width || *update.height != camera.height;
    camera.width = *update.width;
    camera.height = *update.height;
  }
  return resized;
}

}  // namespace gistream
