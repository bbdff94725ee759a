// Exact triangle / axis-aligned box overlap (separating axis theorem,
// Akenine-Moeller 2001). The voxelizer marks every voxel this returns true
// for, which makes the voxelization conservative and therefore watertight.
#pragma once

#include <glm/glm.hpp>

namespace gistream::avg {

// True when triangle (a, b, c) touches the box centred at `center` with
// half-extents `half` (touching faces count as overlap).
bool TriangleBoxOverlap(const glm::vec3& center, const glm::vec3& half, const glm::vec3& a,
                        const glm::vec3& b, const glm::vec3& c);

}  // namespace gistream::avg
