// The environment map as a few directional lights, for the solvers that
// light surfaces through shadow-mapped lights (`direct`, `avg`,
// `sh_probes`, `antiradiance`; `implicit_visibility` gathers the
// environment through its empty bins, `pathtrace` samples it).
// Debevec 2005, "A Median Cut Algorithm for Light Probe Sampling": the
// equirectangular map is cut, region by region, across its longer side
// (in angle) where the energy (luminance x solid angle) halves, the region
// of most energy first, into `count` regions; each becomes a directional
// light at its energy centroid carrying its irradiance sum L d(omega), so
// a surface facing the region receives what the region sends it.
//
// The map's convention is the path tracer's (shading/env_light.h):
// theta = acos(y) from the top row, phi = atan2(x, -z) - rotation.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "scene/state/scene_state.h"

namespace gistream {

struct EnvironmentRegionLight {
  glm::vec3 to_sky{0.0f, 1.0f, 0.0f};  // unit, from the scene towards the region
  glm::vec3 irradiance{0.0f};          // sum of L d(omega) over the region (lux)
};

// The median cut of `image` (linear float RGBA) into at most `count`
// regions with light (none for an empty or black map), unrotated and at
// intensity 1.
std::vector<EnvironmentRegionLight> MedianCutEnvironment(const Image& image, int count);

// The cut turned by `rotation` (radians about +Y) and scaled by `intensity`,
// as the path tracer turns and scales the map.
std::vector<EnvironmentRegionLight> PlaceEnvironmentLights(
    const std::vector<EnvironmentRegionLight>& cut, float rotation, float intensity);

// `state`'s environment (its current rotation and intensity) as `count`
// lights; none without an environment or with count 0.
std::vector<EnvironmentRegionLight> EnvironmentLights(const SceneState& state, int count);

// Turns kChangeEnvironment into kChangeLights for a solver that lights the
// environment as EnvironmentLights: a rotation or intensity change is a
// change of those lights.
ChangeMask EnvironmentAsLights(ChangeMask changes, const SceneState& state);

}  // namespace gistream
