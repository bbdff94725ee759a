#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

namespace gistream {
namespace {

// The rotation of an affine world matrix, whatever its scale: its axes
// orthonormalised in double precision (Gram-Schmidt from the view axis).
// glm::decompose fails once |det| is under float epsilon (a root scale
// below ~4.9e-3) and left the camera undefined: a black frame.
glm::quat RotationOf(const glm::mat4& world) {
  const glm::dmat3 m(world);
  const glm::dvec3 z = m[2], y = m[1];
  const double lz = glm::length(z);
  if (!(lz > 0.0) || !std::isfinite(lz)) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  const glm::dvec3 zn = z / lz;
  glm::dvec3 yo = y - glm::dot(y, zn) * zn;
  const double ly = glm::length(yo);
  if (!(ly > 0.0) || !std::isfinite(ly)) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  yo /= ly;
  const glm::dvec3 x = glm::cross(yo, zn);
  return glm::normalize(glm::quat(glm::quat_cast(glm::dmat3(x, yo, zn))));
}

void FromSceneCamera(const SceneState& state, int node, ViewCamera& camera) {
  const Scene& scene = state.scene();
  const glm::mat4& world = state.world()[size_t(node)];
  camera.position = glm::vec3(world[3]);
  camera.rotation = RotationOf(world);
  camera.yfov = scene.cameras[size_t(scene.nodes[size_t(node)].camera)].yfov;
  camera.scene_camera_node = node;
}

}  // namespace

glm::mat4 ViewCamera::View() const {
  return glm::inverse(glm::translate(glm::mat4(1.0f), position) * glm::mat4_cast(rotation));
}

glm::mat4 ViewCamera::Projection() const {
  const float aspect = float(width) / float(std::max<uint32_t>(height, 1));
  const glm::mat4 p = zfar > znear ? glm::perspective(yfov, aspect, znear, zfar)
                                   : glm::infinitePerspective(yfov, aspect, znear);
  if (jitter == glm::vec2(0.0f)) return p;
  // A pixel is 2 / width NDC units wide: translate clip space by
  // 2 jitter / size, times w (so after the divide, every depth alike).
  const glm::vec2 ndc =
      2.0f * jitter /
      glm::vec2(float(std::max<uint32_t>(width, 1)), float(std::max<uint32_t>(height, 1)));
  glm::mat4 shift(1.0f);
  shift[3] = glm::vec4(ndc, 0.0f, 1.0f);
  return shift * p;
}

glm::vec3 ViewCamera::RayDirection(glm::vec2 ndc) const {
  const float aspect = float(width) / float(std::max<uint32_t>(height, 1));
  const float t = std::tan(0.5f * yfov);
  // Camera space looks down -Z with +Y up; the film at distance 1 spans
  // [-t aspect, t aspect] x [-t, t].
  const glm::vec3 d(ndc.x * t * aspect, ndc.y * t, -1.0f);
  return glm::normalize(rotation * d);
}

ViewCamera WithDepthRange(ViewCamera camera, const SceneState& state, const Bounds& world_bounds) {
  const Bounds& b = world_bounds;
  const float diagonal = b.empty() ? 1.0f : std::max(glm::length(b.extent()), 1e-30f);
  // The glTF camera's planes, in world units (scaled with the node's world
  // scale, cube root of |det|, like its position); 0 when not given.
  float gltf_near = 0.0f, gltf_far = 0.0f;
  const Scene& scene = state.scene();
  const int node = camera.scene_camera_node;
  if (node >= 0 && size_t(node) < scene.nodes.size() && scene.nodes[size_t(node)].camera >= 0) {
    const Camera& c = scene.cameras[size_t(scene.nodes[size_t(node)].camera)];
    const float det = std::abs(glm::determinant(glm::mat3(state.world()[size_t(node)])));
    const float s = std::isfinite(det) && det > 0.0f ? std::cbrt(det) : 1.0f;
    if (std::isfinite(c.znear * s) && c.znear * s > 0.0f) gltf_near = c.znear * s;
    if (std::isfinite(c.zfar * s) && c.zfar * s > 0.0f) gltf_far = c.zfar * s;
  }
  // A point at distance d inside the frustum lies at view depth >= d cos(a),
  // a = the half angle of the frustum's diagonal.
  const float aspect = float(camera.width) / float(std::max<uint32_t>(camera.height, 1));
  const float t = std::tan(0.5f * camera.yfov);
  const float cos_diagonal = 1.0f / std::sqrt(1.0f + t * t * (1.0f + aspect * aspect));
  float near = gltf_near > 0.0f ? gltf_near : 1e-3f * diagonal, d_far = diagonal;
  if (!b.empty()) {
    const glm::vec3 p = camera.position;
    const glm::vec3 farthest = glm::max(glm::abs(b.min - p), glm::abs(b.max - p));
    d_far = glm::length(farthest);
    // A lower bound on the view depth of anything in the box and the
    // frustum: the nearest corner's depth when the whole box is in front,
    // and the box's distance x cos(a) when the camera is outside it.
    const glm::vec3 forward = camera.rotation * glm::vec3(0.0f, 0.0f, -1.0f);
    float z_min = std::numeric_limits<float>::max();
    for (int i = 0; i < 8; ++i) {
      const glm::vec3 corner((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                             (i & 4) ? b.max.z : b.min.z);
      z_min = std::min(z_min, glm::dot(corner - p, forward));
    }
    const float d_out = glm::length(glm::clamp(p, b.min, b.max) - p);
    const float safe = 0.99f * std::max(z_min, d_out * cos_diagonal);
    if (safe > 0.0f) {
      // Nothing visible lies nearer: this near plane clips nothing, a larger
      // glTF znear clips what its author meant to.
      near = std::max(safe, gltf_near);
    } else {
      // Inside the box, part of it behind the camera: geometry can be
      // anywhere. The glTF znear (else 1e-3 of the diagonal), but at most
      // half the distance to the nearest face (or 1e-3 of the diagonal when
      // that is less), so geometry scaled down around a camera that was not
      // is not clipped.
      const glm::vec3 in = glm::min(p - b.min, b.max - p);
      const float d_in = std::min({in.x, in.y, in.z});
      near = std::min(near, std::max(0.5f * d_in * cos_diagonal, 1e-3f * diagonal));
    }
  }
  camera.znear = std::max({near, 1e-7f * diagonal, 1e-30f});
  camera.zfar = gltf_far > 0.0f ? gltf_far : 1.01f * d_far;
  if (!(camera.zfar > camera.znear * 1.0001f)) camera.zfar = 0.0f;  // infinite
  return camera;
}

ViewCamera DefaultCamera(const SceneState& state, uint32_t width, uint32_t height) {
  ViewCamera camera;
  camera.width = width;
  camera.height = height;
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
    camera.rotation =
        glm::normalize(glm::quat_cast(glm::inverse(glm::lookAt(l.eye, l.target, up))));
    camera.scene_camera_node = -1;
  } else if (update.pose) {
    camera.position = update.pose->position;
    camera.rotation = glm::normalize(update.pose->rotation);
    camera.scene_camera_node = -1;
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
