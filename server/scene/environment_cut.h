// An environment map cut into a few regions of equal energy, each a
// directional light (Debevec 2005, "A Median Cut Algorithm for Light Probe
// Sampling"): the region of most energy (luminance x solid angle) is cut
// across its longer side (in angle) where its energy halves, until
// `count` regions; each is a light at its energy centroid carrying its
// irradiance sum L d(omega), so a surface facing the region receives what
// the region sends it. Made once per map at load (scene_import), used by
// the solvers that light the environment through shadow-mapped lights
// (render/environment_lights.h).
//
// The map's convention is the path tracer's (shading/env_light.h):
// theta = acos(y) from the top row, phi = atan2(x, -z) - rotation.
#pragma once

#include <vector>

#include "scene/scene.h"

namespace gistream {

// The regions a loaded environment map is cut into (Debevec used 16 to
// 64): a uniform sky's irradiance within 8.6 % on every normal (16: 21 %,
// 64: 3.3 %; EnvironmentLights.*), 32 directional shadow maps.
inline constexpr int kEnvironmentLightCount = 32;

// The median cut of `image` (linear float RGBA) into at most `count`
// regions with light (none for an empty or black map), unrotated and at
// intensity 1. Texels are summed into at most 512 x 256 cells first, so
// the work memory is bounded whatever the map's size (a cut of 32 regions
// is far coarser than the cells).
std::vector<EnvironmentRegionLight> MedianCutEnvironment(const Image& image, int count);

}  // namespace gistream
