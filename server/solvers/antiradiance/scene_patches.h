// The scene's world-space triangles for the antiradiance hierarchy: one
// group per mesh node instance of a primitive, tagged with its material,
// oriented by the vertex normals (the side that reflects).
#pragma once

#include <vector>

#include "scene/state/scene_state.h"
#include "solvers/antiradiance/patches.h"

namespace gistream::antiradiance {

std::vector<std::vector<SourceTriangle>> SceneTriangles(const SceneState& state);

// Diffuse albedo of a material id (-1: the glTF default material, white).
glm::vec3 MaterialAlbedo(const SceneState& state, int material);

}  // namespace gistream::antiradiance
