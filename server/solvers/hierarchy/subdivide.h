// Elements sized from the scene: the vertex-based solvers (one element per
// mesh vertex) subdivide triangles whose edges are longer than a target
// size before making elements, so a coarse mesh (a Cornell box of 64
// vertices, as the common OBJ versions are) gets elements as fine as a
// tessellated one. Deviation from Dong et al. 2007 and Dachsbacher et al.
// 2007, whose meshes come finely tessellated.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "scene/gpu/gpu_scene.h"
#include "scene/scene.h"

namespace gistream::hierarchy {

// The longest element edge as a fraction of the scene's diagonal: the
// bundled tessellated scenes (longest edges 0.03-0.08 of it) are left as
// they are.
inline constexpr float kMaxElementEdge = 0.1f;

// The vertices SubdivideLongEdges added, in order: vertex n + k (n the
// input's vertex count) is the midpoint of midpoints[k][0] and [1].
using Midpoints = std::vector<std::array<uint32_t, 2>>;

// `primitive` with every edge longer than `max_edge` (its local units)
// split at its midpoint, repeatedly (edges are split, not triangles, so
// the mesh stays free of T-junctions; positions, normals and uvs are
// interpolated). Unchanged when no edge is that long or max_edge <= 0.
// When `midpoints` is given, the added vertices' parents go there.
Primitive SubdivideLongEdges(const Primitive& primitive, float max_edge,
                             Midpoints* midpoints = nullptr);

// The same with the test of an edge given: `too_long(a, b)` (positions in
// the primitive's space) says whether edge (a, b) is split. A test that
// depends on the edge alone keeps the mesh free of T-junctions.
using EdgeTest = std::function<bool(const glm::vec3&, const glm::vec3&)>;
Primitive SubdivideEdges(const Primitive& primitive, const EdgeTest& too_long,
                         Midpoints* midpoints = nullptr);

// The same subdivision repeated on another pose of the same mesh (a
// deformed `primitive`: same vertices and indices, other positions and
// normals): `subdivided`'s triangles and uvs, its added vertices the
// midpoints of the posed ones, as SubdivideLongEdges makes them. So a
// deforming mesh keeps the element layout of the pose it was subdivided at.
Primitive RepeatSubdivision(const Primitive& primitive, const Primitive& subdivided,
                            const Midpoints& midpoints);

// The local-space edge limit for (mesh, primitive): kMaxElementEdge x the
// current world diagonal over the largest scale of its instances.
float LocalMaxEdge(const SceneState& state, const GpuScene& gpu, int mesh, int primitive);

// An upper bound, computed without subdividing, on the vertices of every
// instanced primitive after SubdivideLongEdges (memory estimates, before
// anything is built): a triangle whose longest edge is L becomes at most
// the (n + 1)(n + 2) / 2 points of its n-fold uniform subdivision, n the
// power of two at or above L / max_edge (midpoint splits halve edges).
// Made of the proxy level the element builders take
// (hierarchy/element_source.h: ElementLevel), unless `full_detail`.
// `double_sided_twice`: a primitive of a doubleSided material counts
// twice (antiradiance mirrors its leaves, antiradiance/patches.h).
uint64_t SubdividedVertexBound(const SceneState& state, const GpuScene& gpu, bool full_detail,
                               bool double_sided_twice = false);

}  // namespace gistream::hierarchy
