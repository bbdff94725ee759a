#include "render/environment_lights.h"

#include <cmath>

namespace gistream {
std::vector<EnvironmentRegionLight> PlaceEnvironmentLights(
    const std::vector<EnvironmentRegionLight>& cut, float rotation, float intensity) {
  // phi = atan2(x, -z) - rotation: a texel at phi is seen at phi + rotation.
  const float c = std::cos(rotation), s = std::sin(rotation);
  std::vector<EnvironmentRegionLight> out;
  out.reserve(cut.size());
  for (const EnvironmentRegionLight& l : cut) {
    const glm::vec3 d = l.to_sky;
    out.push_back({glm::vec3(d.x * c - d.z * s, d.y, d.x * s + d.z * c), l.irradiance * intensity});
  }
  return out;
}

std::vector<EnvironmentRegionLight> EnvironmentLights(const SceneState& state) {
  const std::optional<Environment>& env = state.scene().environment;
  if (!env) return {};
  return PlaceEnvironmentLights(env->light_cut, state.environment_rotation(),
                                state.environment_intensity());
}

ChangeMask EnvironmentAsLights(ChangeMask changes, const SceneState& state) {
  if ((changes & kChangeEnvironment) && state.scene().environment) changes |= kChangeLights;
  return changes;
}

}  // namespace gistream
