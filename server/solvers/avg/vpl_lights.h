// The light sources VPL paths start from (paper Sec. III-B), with their
// emitted power in the units the rest of gistream uses: an emissive
// triangle of radiance L (nits) and area A emits pi L A; a point light of
// intensity I (cd) 4 pi I; a spot light I times the solid-angle integral of
// its glTF cone falloff; a directional light of illuminance E (lux) E times
// the cross-section of the disc it covers the grid with.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "render/area_lights.h"
#include "scene/state/scene_state.h"

namespace gistream::avg {

enum class VplLightKind { kArea, kPoint, kSpot, kDirectional };

struct VplLight {
  VplLightKind kind = VplLightKind::kPoint;
  glm::vec3 p0{0.0f}, p1{0.0f}, p2{0.0f};  // kArea: the triangle
  glm::vec3 position{0.0f};                // kPoint/kSpot; kDirectional: disc centre
  glm::vec3 normal{0.0f, 0.0f, -1.0f};     // kArea: emitting side; others: shining direction
  glm::vec3 radiance{0.0f};                // kArea: nits; kPoint/kSpot: cd; kDirectional: lux
  float cone_scale = 0.0f, cone_offset = 0.0f, cos_outer = -1.0f;  // kSpot (KHR_lights_punctual)
  float disc_radius = 0.0f;                                        // kDirectional
  glm::vec3 power{0.0f};                                           // emitted flux (W)
};

// Every light of `state`: emissive triangles and punctual lights, and with
// `environment_lights` the environment's directional lights (render/
// environment_lights.h). Directional lights cover a disc of radius
// `scene_radius` around `scene_center` (the voxel grid's bounding sphere).
std::vector<VplLight> CollectVplLights(const SceneState& state, const glm::vec3& scene_center,
                                       float scene_radius, bool environment_lights = false);

// Solid-angle integral of the KHR_lights_punctual spot falloff, in sr.
float SpotSolidAngle(float cone_scale, float cone_offset, float cos_outer);

}  // namespace gistream::avg
