// Procedural meshes for tests that build a Scene in memory rather than
// importing a glTF file: a subdivided floor and a UV sphere, each with
// per-vertex normals and bounds.
#pragma once

#include <memory>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace gistream::testing {

// The square [-half, half]^2 at y = 0, normal +y, as n x n quads.
Primitive FloorGrid(int n, float half = 1.0f);

// A sphere as rings x segments quads (poles included), outward normals.
Primitive UvSphere(const glm::vec3& center, float radius, int rings, int segments);

// A floor of floor_quads^2 quads over [-1, 1]^2 under a sphere of radius 0.3
// at (0, 0.5, 0) of rings x segments quads: one mesh and one root node each.
// With `with_proxies` the scene also gets its simplified levels
// (BuildSceneProxies), as an import would.
std::shared_ptr<const Scene> FloorAndSphereScene(int floor_quads, int rings, int segments,
                                                 bool with_proxies);

}  // namespace gistream::testing
