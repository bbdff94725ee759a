// The six 90-degree views of a cube map around a point, shared by every
// cube rendered from a point (render/shadow_maps' light cubes, avg's VPL
// distance cubes): the uFaceViewProj of shaders/render/shadow_cube.geom.glsl.
#pragma once

#include <array>

#include <glm/glm.hpp>

namespace gistream {

// View-projections of the faces in GL cube-map order (+X, -X, +Y, -Y, +Z,
// -Z) around `origin`, near plane far * 1e-5, far plane `far`.
std::array<glm::mat4, 6> CubeFaceViewProj(const glm::vec3& origin, float far);

// Bit f set for each face f whose frustum reaches the hemisphere around
// `normal` (some corner direction at or above it); a face without its bit
// sees only what lies behind the hemisphere.
int HemisphereFaceMask(const glm::vec3& normal);

}  // namespace gistream
