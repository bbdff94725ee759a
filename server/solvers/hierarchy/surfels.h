// Surface elements at the finest level (Dong et al. 2007, Section 4.1):
// one oriented disc per vertex of a triangle mesh, with the vertex's normal
// and one third of the area of the triangles that share it (as in Bunnell
// 2005). Computed once per mesh primitive, in its local space
// (create_surfels).
//
// Deviation: the disc is centred on the centroid of that third of the area
// rather than on the vertex. Inside a mesh the two coincide; on a border
// (a box's edge) the vertex lies in the neighbouring face's plane, where
// that face covers no solid angle and the element would gather only half
// its hemisphere.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace gistream::hierarchy {

struct Surfels {
  std::vector<glm::vec3> position;  // local space, centroid of the vertex's area
  std::vector<glm::vec3> normal;    // unit; a zero vertex normal becomes the face normal
  std::vector<float> area;          // one third of the adjacent triangles' areas

  size_t size() const { return position.size(); }
};

Surfels CreateSurfels(const Primitive& primitive);

}  // namespace gistream::hierarchy
