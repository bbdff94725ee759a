// The exact point-to-polygon form factor (Lambert's formula; Cohen and
// Wallace, "Radiosity and Realistic Image Synthesis", Eq. 4.27): the
// fraction of a receiver point's irradiance that a uniform diffuse planar
// polygon of radiance L sends, E = pi L F. The polygon is first clipped to
// the receiver's front half-space, so a polygon that straddles the
// receiver's plane counts only its visible part.
//
// Used for the links between leaves close to each other, where Eq. 17's
// point-to-point kernel (and any point-to-disc variant) misjudges the
// solid angle: at a box's edges it lost 7 to 20 % of each leaf's
// irradiance (docs/ARCHITECTURE.md, the antiradiance solver's Energy).
#pragma once

#include <array>
#include <span>

#include <glm/glm.hpp>

namespace gistream::antiradiance {

// A planar convex quad; a triangle repeats its last corner.
using CellQuad = std::array<glm::vec3, 4>;

// Sum over the quads of the point-to-polygon form factor seen from point x
// with unit normal n (each quad clipped to n . (p - x) >= 0). In [0, 1]
// for quads that do not overlap as seen from x.
double PointToQuadsFormFactor(std::span<const CellQuad> quads, const glm::vec3& x,
                              const glm::vec3& n);

}  // namespace gistream::antiradiance
