// Vertex normals for primitives that come without them.
#pragma once

#include "scene/scene.h"

namespace gistream {

// Fills primitive->normals with area-weighted vertex normals, facing the
// side from which the triangles wind counter-clockwise. Where triangles
// sharing a vertex meet at more than a crease angle, the vertex is split so
// the edge stays hard: glTF asks for flat normals when a file has none, and
// a box whose corners are shared must still render as a box. Positions and
// uvs of split vertices are duplicated; indices are rewritten.
void GenerateNormals(Primitive* primitive);

}  // namespace gistream
