#include "solvers/hierarchy/surfels.h"

#include <cmath>

namespace gistream::hierarchy {

Surfels CreateSurfels(const Primitive& primitive) {
  Surfels s;
  const size_t n = primitive.positions.size();
  s.position = primitive.positions;
  s.normal.assign(n, glm::vec3(0.0f));
  s.area.assign(n, 0.0f);
  std::vector<glm::vec3> face_normal_sum(n, glm::vec3(0.0f));
  std::vector<glm::vec3> centroid_sum(n, glm::vec3(0.0f));
  for (size_t i = 0; i + 2 < primitive.indices.size(); i += 3) {
    const uint32_t a = primitive.indices[i], b = primitive.indices[i + 1],
                   c = primitive.indices[i + 2];
    if (a >= n || b >= n || c >= n) continue;
    const glm::vec3 cross =
        glm::cross(s.position[b] - s.position[a], s.position[c] - s.position[a]);
    const float area = 0.5f * glm::length(cross);
    if (!std::isfinite(area)) continue;
    const uint32_t tri[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = tri[k];
      const glm::vec3& p = primitive.positions[v];
      const glm::vec3& q = primitive.positions[tri[(k + 1) % 3]];
      const glm::vec3& r = primitive.positions[tri[(k + 2) % 3]];
      s.area[v] += area / 3.0f;
      face_normal_sum[v] += cross;
      // The vertex's third of the triangle (v, mid(v,q), centroid,
      // mid(v,r)), its corners averaged: 7/12 v + 5/24 (q + r).
      centroid_sum[v] += (area / 3.0f) * ((7.0f / 12.0f) * p + (5.0f / 24.0f) * (q + r));
    }
  }
  for (size_t v = 0; v < n; ++v) {
    if (s.area[v] > 0.0f) s.position[v] = centroid_sum[v] / s.area[v];
    glm::vec3 normal = v < primitive.normals.size() ? primitive.normals[v] : glm::vec3(0.0f);
    float len = glm::length(normal);
    if (!(len > 0.0f) || !std::isfinite(len)) {
      normal = face_normal_sum[v];
      len = glm::length(normal);
    }
    s.normal[v] = len > 0.0f && std::isfinite(len) ? normal / len : glm::vec3(0.0f, 1.0f, 0.0f);
  }
  return s;
}

}  // namespace gistream::hierarchy
