#include <numbers>
#include <string>

#include "scene/gltf/gltf_stages.h"
#include "scene/gltf/gltf_util.h"
#include "scene/magnitude_limits.h"

namespace gistream::gltf {

absl::StatusOr<std::vector<Light>> ImportLights(const tinygltf::Model& model) {
  std::vector<Light> lights;
  for (size_t i = 0; i < model.lights.size(); ++i) {
    const tinygltf::Light& in = model.lights[i];
    const std::string field = Item("extensions.KHR_lights_punctual.lights", i);
    Light light;
    light.name = in.name;
    if (in.type == "point") {
      light.type = LightType::kPoint;
    } else if (in.type == "spot") {
      light.type = LightType::kSpot;
    } else if (in.type == "directional") {
      light.type = LightType::kDirectional;
    } else {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".type: '", in.type, "' is not point, spot or directional"));
    }
    if (!in.color.empty()) {
      if (in.color.size() != 3) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ".color: ", in.color.size(), " values, expected 3"));
      }
      GS_RETURN_IF_ERROR(CheckRange(field + ".color", in.color, 0.0, kMaxFloat));
      light.color = glm::vec3(in.color[0], in.color[1], in.color[2]);
    }
    GS_RETURN_IF_ERROR(CheckNumber(field + ".intensity", in.intensity, 0.0, kMaxRadiance));
    GS_RETURN_IF_ERROR(CheckNumber(field + ".range", in.range, 0.0, kMaxFloat));
    light.intensity = static_cast<float>(in.intensity);
    light.range = static_cast<float>(in.range);
    if (MaxLightStrength(light) > kMaxRadiance) {
      return absl::InvalidArgumentError(absl::StrCat(
          field, ".intensity: ", in.intensity, " x color ",
          MaxLightStrength(light) / light.intensity, " exceeds the limit of ", kMaxRadiance));
    }
    if (light.type == LightType::kSpot) {
      const double half_pi = std::numbers::pi / 2;
      GS_RETURN_IF_ERROR(
          CheckNumber(field + ".spot.outerConeAngle", in.spot.outerConeAngle, 0.0, half_pi));
      GS_RETURN_IF_ERROR(CheckNumber(field + ".spot.innerConeAngle", in.spot.innerConeAngle, 0.0,
                                     in.spot.outerConeAngle));
      light.inner_cone_angle = static_cast<float>(in.spot.innerConeAngle);
      light.outer_cone_angle = static_cast<float>(in.spot.outerConeAngle);
    }
    lights.push_back(std::move(light));
  }
  return lights;
}

}  // namespace gistream::gltf
