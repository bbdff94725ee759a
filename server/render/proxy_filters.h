// Which proxy level and which items the view-independent raster passes
// draw (issue 19): per item, the world box it occupies, the cube faces that
// see any of it, and the geometric error a depth or radiance cube (or a
// paraboloid map) can show at its distance. GpuScene::Draw takes them as a DrawFilter.
#pragma once

#include <functional>

#include <glm/glm.hpp>

#include "scene/gpu/gpu_scene.h"

namespace gistream {

// `item`'s world box under `model` (its primitive box's 8 corners
// transformed: never smaller than the truth); everything for a skinned or
// morphed primitive, whose posed shape may leave its box.
Bounds ItemWorldBounds(const SceneState& state, const DrawItem& item, const glm::mat4& model);

// Bit f set for each cube face f (GL order +X, -X, +Y, -Y, +Z, -Z) around
// `origin` whose 90-degree frustum may hold part of `box`. Conservative: a
// face whose bit is clear sees nothing of the box (a face's frustum is the
// set where the axis coordinate is at least both others' magnitudes; the
// test is that inequality against the box's extremes).
int CubeFaceMask(const Bounds& box, const glm::vec3& origin);

// The world size of one texel of a `resolution`^2 90-degree cube face at
// the nearest distance of `box` from `origin` (2 d / resolution, the
// face-centre texel; the shadow lookup's receiver offset is 1.5 of these,
// shaders/render/direct_light.glsl): a proxy within it moves no surface by
// more than the offset already absorbs. 0 when `origin` is inside the box.
float CubeTexelTolerance(const Bounds& box, const glm::vec3& origin, int resolution);

// The filters of a cube of `resolution`^2 faces around `origin` (shadow
// cubes, sh_probes' probe cubes), for GpuScene::Draw: per item and per
// cluster node, nothing when no face can see its world box (CubeFaceMask),
// else `set_faces` gets the face mask right before the draw (the pass's
// face-mask uniform) and the tolerance is CubeTexelTolerance at the box.
// They refer to `state`, which must outlive them.
struct CubeDrawFilters {
  DrawFilter item;
  ClusterFilter cluster;
};
CubeDrawFilters CubeFilters(const SceneState& state, const glm::vec3& origin, int resolution,
                            std::function<void(int faces)> set_faces);

// The same for a `resolution`^2 paraboloid (hemisphere) map at `origin`
// facing `normal` (avg's VPL maps, Brabec et al. 2002: uv = d.xy / (1 + d.z)
// over [-1, 1]^2, a texel 2 / resolution in uv). Radially r = tan(theta / 2),
// dr / dtheta = 1 / (1 + cos theta); tangentially r dphi = du and the arc is
// sin theta dphi = (1 + cos theta) du: a texel subtends (1 + cos theta) 2 /
// resolution radians, from 2 / resolution at the horizon to 4 / resolution
// on the axis. So 2 d / resolution (d the box's nearest distance) is below
// the texel anywhere in the box and within the one-texel normal offset of
// the lookup (uVplTexel, shaders/avg/illuminate.frag.glsl). The map is not
// linear, though: the rasterizer would draw a triangle's edges straight in
// uv where their true images are arcs (uv is a stereographic projection),
// an edge of length L at distance d up to (L / d)^2 / 8 off in uv, so a
// coarse copy's big triangles would land several texels off even at zero
// geometric error. The VPL pass therefore draws proxies into a distance
// cube (a linear projection, whose face texel is 2 d / resolution at most
// at distance d) and resamples it into the map (avg/vpl_shadow_maps.h).
// < 0 when the whole box is behind the hemisphere (z < 0 in the map's
// frame); 0 when `origin` is inside it.
float ParaboloidTexelTolerance(const Bounds& box, const glm::vec3& origin, const glm::vec3& normal,
                               int resolution);

}  // namespace gistream
