// Which proxy level and which items the view-independent raster passes
// draw (issue 19): per item, the world box it occupies, the cube faces that
// see any of it, and the geometric error a depth or radiance cube can show
// at its distance. GpuScene::Draw takes them as a DrawFilter.
#pragma once

#include <glm/glm.hpp>

#include "scene/gpu_scene.h"

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

}  // namespace gistream
