// Irradiance from elements made of a proxy (hierarchy/element_source.h)
// onto the full mesh's vertices: per display vertex, the nearest triangle
// of the element mesh and the barycentrics of the nearest point on it,
// computed once when the elements are built. The display then draws the
// full mesh (the G-buffer's surface, so every pixel it covers gets
// irradiance) with each vertex's irradiance the weighted sum of three
// leaves'. The nearest point is within the proxy's recorded error of the
// vertex (the error bounds the Hausdorff distance both ways).
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace gistream::hierarchy {

struct VertexTransfer {
  std::vector<glm::uvec3> corner;  // vertices of `from`, per vertex of `to`
  std::vector<glm::vec3> weight;   // barycentrics: >= 0, sum 1
};

// For every vertex of `to`, the nearest triangle of `from` among those
// facing its side (the triangle's summed vertex normals, or its winding,
// within 60 degrees of the vertex normal), any triangle when none does.
// Both in the same (local) space. `from` without triangles: every vertex
// takes vertex 0 of `from` with weight 0.
VertexTransfer TransferVertices(const Primitive& to, const Primitive& from);

}  // namespace gistream::hierarchy
