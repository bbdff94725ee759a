// The element hierarchy the antiradiance solver works on (Dachsbacher et
// al. 2007, Sections 3.2 and 4.1): a forest of patches P_i with centre
// x_i, normal n_i, area a_i and albedo, laid out in depth-first order so
// that a parent precedes its children (push walks forward, pull backward).
//
// This is the small interface the solver needs from a hierarchy (position,
// normal, area, albedo, children). It is built here from the scene's
// triangles (BuildPatches); the shared hierarchy of `implicit_visibility`
// (server/solvers/hierarchy/) can fill the same struct later.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/antiradiance/form_factor.h"

namespace gistream::antiradiance {

struct Patches {
  // Per node (leaves and clusters).
  std::vector<glm::vec3> position;  // centre x_i (area-weighted)
  std::vector<glm::vec3>
      normal;                 // unit for leaves; clusters: area-weighted average (unused by K/J)
  std::vector<float> area;    // a_i, the sum of the leaves' areas for a cluster
  std::vector<float> radius;  // bounding sphere about position
  std::vector<glm::vec3> albedo;  // leaves: diffuse reflectance rho
  std::vector<int> tag;           // leaves: the source triangle's tag (e.g. its material)
  std::vector<std::array<int, 4>> children;  // up to four; -1 unused (all -1 for leaves)
  std::vector<int> roots;                    // one per mesh instance
  // Leaves: the surface each stands for, as planar quads (world space): a
  // triangle patch its triangle, a vertex disc its vertex's third of each
  // adjacent triangle. Quads of node i are cell[cell_begin[i] ..
  // cell_begin[i + 1]); cell_begin is empty when no cells are known (links
  // then use Eq. 17's kernel only).
  std::vector<CellQuad> cell;
  std::vector<uint32_t> cell_begin;

  int size() const { return int(position.size()); }
  bool is_leaf(int i) const { return children[size_t(i)][0] < 0; }
  std::vector<int> Leaves() const;
  std::span<const CellQuad> Cell(int i) const {
    if (cell_begin.size() != size_t(size()) + 1) return {};
    return {cell.data() + cell_begin[size_t(i)], cell.data() + cell_begin[size_t(i) + 1]};
  }
};

// One world-space triangle of the scene with its material's albedo.
struct SourceTriangle {
  std::array<glm::vec3, 3> p;
  glm::vec3 normal;  // unit, the side that reflects
  glm::vec3 albedo;
  int tag = -1;
};

// Triangles longer than `max_edge` are split 1-to-4 until they are not;
// each group (a mesh instance) becomes one binary tree, split at the median
// along the widest extent of (centre, 0.3 x size x normal) so siblings are
// adjacent and similarly oriented.
Patches BuildPatches(const std::vector<std::vector<SourceTriangle>>& groups, float max_edge);
// How many leaves BuildPatches would make at most (degenerate ones are
// dropped), without making them: each split halves every edge, so a
// triangle with longest edge e becomes 4^d leaves, d = halvings to reach
// max_edge (at most 12). For checking a memory budget before building.
uint64_t CountLeaves(const std::vector<std::vector<SourceTriangle>>& groups, float max_edge);

// glTF doubleSided (2.0 3.9.2: the back face is a surface with the flipped
// normal): every root whose leaves' tags all satisfy `two_sided` gets a
// mirrored copy, appended as a root of its own, with the same positions,
// areas, albedos and cells and negated normals. The paper treats solid
// objects only (Section 3.2, Fig. 7: a leaf gathers and reflects over its
// positive hemisphere and sends antiradiance into its negative one); an
// open double-sided sheet is two such surfaces back to back, so the light
// that reaches its back is reflected there and blocked from passing
// through (a lamp 1 cm under a ceiling: the ceiling's light went through
// it into the room). Returns the number of roots mirrored.
int AddBackFaces(Patches& p, const std::function<bool(int tag)>& two_sided);

}  // namespace gistream::antiradiance
