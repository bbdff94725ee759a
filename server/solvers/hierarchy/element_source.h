// The mesh the element hierarchy is made of (issue 19): a primitive with
// proxy levels (scene/proxies/proxy_levels.h) gives its elements from the coarsest
// level whose recorded error is within kProxyErrorFraction of the element
// target size (the subdivision limit, hierarchy/subdivide.h), and that
// level is then subdivided as a full mesh would be. Dong et al. 2007 and
// Dachsbacher et al. 2007 build their elements from a simplified
// hierarchy, not from the render mesh.
#pragma once

#include "scene/scene.h"

namespace gistream::hierarchy {

// Primitives with fewer triangles keep their full mesh (as the cluster
// trees start above 4,096, scene/proxies/proxy_clusters.h): the white furnace's
// cube (3,072 triangles) lost 5.6 % of its energy at albedo 0.99 with
// implicit_visibility's elements made from its 48-triangle level, whose
// faces meet in T-junctions along the cube's edges (EverySolver/Furnace
// allows 3 %; why it loses was not found), and on the bundled scenes'
// meshes (1,152 triangles and fewer) the elements cost little anyway.
inline constexpr size_t kMinProxyTriangles = 4096;

// A level may move the surface by this fraction of the subdivision limit.
// A disc sits at its area centroid and a leaf is at most the limit wide,
// so a surface moved by x of the limit moves each disc by at most about x
// of its size; a form factor A cos cos / (pi r^2) between neighbours (r about one
// element size) then changes by O(x) (r by x of itself, the normals by an
// angle of O(x)): 10 % for the nearest pairs, less with distance
// (relative change x size / r).
inline constexpr float kProxyErrorFraction = 0.1f;

// The proxy level the elements of `primitive` are made of: the coarsest
// whose recorded error is within kProxyErrorFraction x `max_edge` (local
// units, as hierarchy::LocalMaxEdge); -1 (the full mesh) with
// `full_detail`, below kMinProxyTriangles, when none is, or when
// max_edge <= 0.
int ElementLevel(const Primitive& primitive, float max_edge, bool full_detail);

// Level `level`'s triangles over the vertices it uses, in their order in
// `primitive` (positions, normals and uvs copied; material and bounds; no
// proxies, clusters, skin or morph targets), with coplanar slivers flipped
// towards the Delaunay triangulation (the surface unchanged).
Primitive ProxyLevelMesh(const Primitive& primitive, int level);

// `primitive`'s surface alone: positions, normals, uvs, indices, material
// and bounds (what the display needs; no proxies or clusters).
Primitive SurfaceOf(const Primitive& primitive);

}  // namespace gistream::hierarchy
