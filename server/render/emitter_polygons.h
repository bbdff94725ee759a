// Emitter triangles merged into convex polygons for the exact (unoccluded)
// irradiance of render/direct_light.glsl: Lambert's polygon formula
// (Baum et al. 1989, eq. 2; Arvo 1995, "Applications of irradiance
// tensors", eq. 9) gives the irradiance from a uniformly emitting polygon
// in closed form, where the area samples' disc estimate is badly low near
// an emitter's edges (a receiver a few centimetres from an emitting wall).
// The samples still give the visibility (their shadow maps), as a ratio of
// shadowed to unshadowed sample sums per polygon (Heitz et al. 2018,
// "Combining analytic direct illumination and stochastic shadows", eq. 3).
#pragma once

#include <array>
#include <vector>

#include <glm/glm.hpp>

#include "render/area_lights.h"

namespace gistream {

struct EmitterPolygon {
  static constexpr int kMaxVertices = 8;
  std::array<glm::vec3, kMaxVertices> vertices{};
  int vertex_count = 0;
  glm::vec3 normal{0.0f};  // the emitting side
  glm::vec3 radiance{0.0f};
  float area = 0.0f;
};

// At most this many polygons: beyond it (a finely tessellated curved
// emitter) the exact term is not used and the samples' disc estimate is.
inline constexpr int kMaxEmitterPolygons = 64;

struct EmitterPolygons {
  std::vector<EmitterPolygon> polygons;
  std::vector<int> polygon_of_triangle;  // index into polygons per emitter triangle
};

// Coplanar triangles of equal radiance and side whose union is convex
// (its convex hull's area equals the sum of theirs) with at most
// kMaxVertices hull corners become one polygon; any other triangle is a
// polygon of its own. Empty (no polygons) when more than
// kMaxEmitterPolygons would result.
EmitterPolygons MergeEmitterPolygons(const std::vector<EmitterTriangle>& emitters);

}  // namespace gistream
