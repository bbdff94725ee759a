// The environment map as a few directional lights, for the solvers that
// light surfaces through shadow-mapped lights (`direct`, `avg`,
// `sh_probes`, `antiradiance`; `implicit_visibility` gathers the
// environment through its empty bins, `pathtrace` samples it): the map's
// median cut, made at load (scene/environment_cut.h), turned and scaled
// as the scene's environment is now.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/environment_cut.h"
#include "scene/scene.h"
#include "scene/state/scene_state.h"

namespace gistream {

// The cut turned by `rotation` (radians about +Y) and scaled by `intensity`,
// as the path tracer turns and scales the map.
std::vector<EnvironmentRegionLight> PlaceEnvironmentLights(
    const std::vector<EnvironmentRegionLight>& cut, float rotation, float intensity);

// `state`'s environment (its current rotation and intensity) as the lights
// of its load-time cut (kEnvironmentLightCount of them); none without one.
std::vector<EnvironmentRegionLight> EnvironmentLights(const SceneState& state);

// Turns kChangeEnvironment into kChangeLights for a solver that lights the
// environment as EnvironmentLights: a rotation or intensity change is a
// change of those lights.
ChangeMask EnvironmentAsLights(ChangeMask changes, const SceneState& state);

}  // namespace gistream
