// CPU form of the illumination step (Section 4.3): gather at the leaves
// along the pushed-down links, then pull up by area. The solvers run the
// same arithmetic in GL compute (shaders/implicit_visibility/gather.comp.glsl
// and pull.comp.glsl); this version is the reference the tests check them
// and the hierarchy against.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "solvers/hierarchy/elements.h"
#include "solvers/hierarchy/links.h"
#include "solvers/hierarchy/refine_push.h"

namespace gistream::hierarchy {

// Irradiance at every leaf: E_i = sum_k w_k L(source_k) (Eq. 5 summed over
// the bins, Eq. 2).
std::vector<glm::vec3> Gather(const LeafLinks& links, const std::vector<glm::vec3>& radiance);

// Fills the internal nodes of `radiance` (node_count entries, leaves set):
// each node the area-weighted average of its children ("pull up").
void PullUp(const Elements& elements, std::vector<glm::vec3>& radiance);

}  // namespace gistream::hierarchy
