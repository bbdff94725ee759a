#include "render/cube_faces.h"

#include <glm/gtc/matrix_transform.hpp>

namespace gistream {
namespace {

// GL cube-map face orientations (+X, -X, +Y, -Y, +Z, -Z).
constexpr glm::vec3 kDir[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
constexpr glm::vec3 kUp[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1},
                              {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};

}  // namespace

std::array<glm::mat4, 6> CubeFaceViewProj(const glm::vec3& origin, float far) {
  const glm::mat4 proj = glm::perspective(glm::half_pi<float>(), 1.0f, far * 1e-5f, far);
  std::array<glm::mat4, 6> view_proj;
  for (int f = 0; f < 6; ++f) {
    view_proj[size_t(f)] = proj * glm::lookAt(origin, origin + kDir[f], kUp[f]);
  }
  return view_proj;
}

int HemisphereFaceMask(const glm::vec3& normal) {
  int mask = 0;
  for (int f = 0; f < 6; ++f) {
    const glm::vec3 u = kUp[f], v = glm::cross(kDir[f], kUp[f]);
    for (const float su : {-1.0f, 1.0f}) {
      for (const float sv : {-1.0f, 1.0f}) {
        if (glm::dot(normal, kDir[f] + su * u + sv * v) >= 0.0f) mask |= 1 << f;
      }
    }
  }
  return mask;
}

}  // namespace gistream
