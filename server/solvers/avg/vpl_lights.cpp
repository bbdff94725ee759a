#include "solvers/avg/vpl_lights.h"

#include "render/environment_lights.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

namespace gistream::avg {

float SpotSolidAngle(float cone_scale, float cone_offset, float cos_outer) {
  // 2 pi * integral over cos(theta) in [cos_outer, 1] of the falloff
  // clamp(c * scale + offset, 0, 1)^2 (midpoint rule; smooth integrand).
  constexpr int kSteps = 1024;
  const float lo = std::clamp(cos_outer, -1.0f, 1.0f);
  const float dc = (1.0f - lo) / float(kSteps);
  double sum = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const float c = lo + (float(i) + 0.5f) * dc;
    const float f = std::clamp(c * cone_scale + cone_offset, 0.0f, 1.0f);
    sum += double(f * f);
  }
  return float(2.0 * glm::pi<double>() * sum * double(dc));
}

std::vector<VplLight> CollectVplLights(const SceneState& state, const glm::vec3& scene_center,
                                       float scene_radius, bool environment_lights) {
  std::vector<VplLight> out;
  for (const EmitterTriangle& t : CollectEmitters(state)) {
    VplLight l;
    l.kind = VplLightKind::kArea;
    l.p0 = t.p0;
    l.p1 = t.p1;
    l.p2 = t.p2;
    l.normal = t.normal;
    l.radiance = t.radiance;
    l.power = glm::pi<float>() * t.radiance * t.area;
    out.push_back(l);
  }
  for (const LightInstance& li : state.lights()) {
    VplLight l;
    const glm::vec3 intensity = li.light.color * li.light.intensity;
    l.radiance = intensity;
    l.position = li.position;
    const float len = glm::length(li.direction);
    l.normal = len > 0.0f ? li.direction / len : glm::vec3(0.0f, 0.0f, -1.0f);
    switch (li.light.type) {
      case LightType::kPoint:
        l.kind = VplLightKind::kPoint;
        l.power = 4.0f * glm::pi<float>() * intensity;
        break;
      case LightType::kSpot: {
        l.kind = VplLightKind::kSpot;
        l.cos_outer = std::cos(li.light.outer_cone_angle);
        l.cone_scale = 1.0f / std::max(0.001f, std::cos(li.light.inner_cone_angle) - l.cos_outer);
        l.cone_offset = -l.cos_outer * l.cone_scale;
        l.power = intensity * SpotSolidAngle(l.cone_scale, l.cone_offset, l.cos_outer);
        break;
      }
      case LightType::kDirectional:
        l.kind = VplLightKind::kDirectional;
        l.position = scene_center;
        l.disc_radius = scene_radius;
        l.power = intensity * glm::pi<float>() * scene_radius * scene_radius;
        break;
    }
    out.push_back(l);
  }
  for (const EnvironmentRegionLight& e :
       environment_lights ? EnvironmentLights(state) : std::vector<EnvironmentRegionLight>{}) {
    VplLight l;
    l.kind = VplLightKind::kDirectional;
    l.radiance = e.irradiance;
    l.normal = -e.to_sky;
    l.position = scene_center;
    l.disc_radius = scene_radius;
    l.power = e.irradiance * glm::pi<float>() * scene_radius * scene_radius;
    out.push_back(l);
  }
  // Lights that emit nothing (or NaN from a broken update) take no paths.
  out.erase(std::remove_if(out.begin(), out.end(),
                           [](const VplLight& l) {
                             const float p = l.power.x + l.power.y + l.power.z;
                             return !(p > 0.0f) || !std::isfinite(p);
                           }),
            out.end());
  return out;
}

}  // namespace gistream::avg
