#include "render/proxy_filters.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace gistream {

Bounds ItemWorldBounds(const SceneState& state, const DrawItem& item, const glm::mat4& model) {
  const Primitive& primitive =
      state.scene().meshes[size_t(item.mesh)].primitives[size_t(item.primitive)];
  Bounds world;
  if (!primitive.joints.empty() || !primitive.targets.empty()) {
    // Skinned or morphed: its posed shape may leave the rest-pose box.
    world.Extend(glm::vec3(std::numeric_limits<float>::lowest()));
    world.Extend(glm::vec3(std::numeric_limits<float>::max()));
    return world;
  }
  return primitive.bounds.Transformed(model);
}

int CubeFaceMask(const Bounds& box, const glm::vec3& origin) {
  if (box.empty()) return 0;
  const glm::vec3 lo = box.min - origin, hi = box.max - origin;
  // Smallest |coordinate| over the box per axis (0 when it spans 0).
  const glm::vec3 least = glm::max(glm::max(lo, -hi), glm::vec3(0.0f));
  int mask = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    // Face +axis sees points with x_axis >= |x_u| and x_axis >= |x_v|: it
    // can only when the box's largest x_axis reaches both smallest
    // magnitudes; -axis likewise with -x_axis.
    if (hi[axis] >= least[u] && hi[axis] >= least[v]) mask |= 1 << (2 * axis);
    if (-lo[axis] >= least[u] && -lo[axis] >= least[v]) mask |= 1 << (2 * axis + 1);
  }
  return mask;
}

float CubeTexelTolerance(const Bounds& box, const glm::vec3& origin, int resolution) {
  if (box.empty() || resolution <= 0) return 0.0f;
  const glm::vec3 outside = glm::max(glm::max(box.min - origin, origin - box.max), glm::vec3(0.0f));
  return 2.0f * glm::length(outside) / float(resolution);
}

CubeDrawFilters CubeFilters(const SceneState& state, const glm::vec3& origin, int resolution,
                            std::function<void(int faces)> set_faces) {
  CubeDrawFilters filters;
  filters.cluster = [origin, resolution, set_faces = std::move(set_faces)](const Bounds& box) {
    const int faces = CubeFaceMask(box, origin);
    if (faces == 0) return -1.0f;
    set_faces(faces);
    return CubeTexelTolerance(box, origin, resolution);
  };
  filters.item = [&state, cluster = filters.cluster](const DrawItem& item, const glm::mat4& model) {
    return cluster(ItemWorldBounds(state, item, model));
  };
  return filters;
}

float ParaboloidTexelTolerance(const Bounds& box, const glm::vec3& origin, const glm::vec3& normal,
                               int resolution) {
  if (box.empty()) return -1.0f;
  // The box's largest z in the map's frame: centre plus half extent
  // projected on |normal|.
  const float z_max =
      glm::dot(box.center() - origin, normal) + glm::dot(0.5f * box.extent(), glm::abs(normal));
  if (z_max < 0.0f) return -1.0f;
  // Same bound as the cube's face-centre texel (see the header).
  return CubeTexelTolerance(box, origin, resolution);
}

}  // namespace gistream
