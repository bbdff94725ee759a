#include "scene/state/validate_update.h"

#include <absl/strings/string_view.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "scene/magnitude_limits.h"

namespace gistream {
namespace {

absl::Status Invalid(absl::string_view field, absl::string_view what) {
  return absl::InvalidArgumentError(absl::StrCat("update.", field, ": ", what));
}

absl::Status CheckId(absl::string_view field, uint64_t id, size_t count, absl::string_view things) {
  if (id >= count) {
    return Invalid(field,
                   absl::StrCat(id, " is out of range (the scene has ", count, " ", things, ")"));
  }
  return absl::OkStatus();
}

absl::Status CheckFinite(absl::string_view field, float v) {
  if (!std::isfinite(v)) return Invalid(field, absl::StrCat(v, " is not finite"));
  return absl::OkStatus();
}

absl::Status CheckAtLeast(absl::string_view field, float v, float lo) {
  GS_RETURN_IF_ERROR(CheckFinite(field, v));
  if (v < lo) return Invalid(field, absl::StrCat(v, " is below ", lo));
  return absl::OkStatus();
}

template <int N>
absl::Status CheckVec(absl::string_view field, const glm::vec<N, float>& v, const char* names,
                      float lo = -INFINITY) {
  for (int i = 0; i < N; ++i) {
    const std::string component = absl::StrCat(field, ".", absl::string_view(&names[i], 1));
    GS_RETURN_IF_ERROR(CheckFinite(component, v[i]));
    if (v[i] < lo) return Invalid(component, absl::StrCat(v[i], " is below ", lo));
  }
  return absl::OkStatus();
}

absl::Status CheckAtMost(absl::string_view field, float v, float hi) {
  if (v > hi) return Invalid(field, absl::StrCat(v, " exceeds the limit of ", hi));
  return absl::OkStatus();
}

// Unit length within kQuaternionTolerance (the render thread renormalises).
absl::Status CheckQuat(absl::string_view field, const glm::quat& q) {
  return CheckUnitQuaternion(absl::StrCat("update.", field), q).status();
}

absl::Status CheckPos(absl::string_view field, const glm::vec3& p) {
  return CheckPosition(absl::StrCat("update.", field), p);
}

// Largest component of an RGB triple, for the kMaxRadiance products.
float MaxComponent(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

absl::Status CheckNonZero(absl::string_view field, const glm::vec3& v) {
  GS_RETURN_IF_ERROR(CheckVec<3>(field, v, "xyz"));
  if (!(glm::length(v) > 0.0f)) return Invalid(field, "zero-length vector");
  return absl::OkStatus();
}

absl::Status Check(const Scene& scene, const NodeTransformUpdate& u) {
  GS_RETURN_IF_ERROR(CheckId("node_transform.node", u.node, scene.nodes.size(), "nodes"));
  if (u.matrix) {
    const glm::mat4& m = *u.matrix;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) {
        GS_RETURN_IF_ERROR(
            CheckFinite(absl::StrCat("node_transform.matrix[", c, "][", r, "]"), m[c][r]));
      }
    }
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f) {
      return Invalid("node_transform.matrix", "bottom row is not (0, 0, 0, 1)");
    }
    if (!(std::abs(glm::determinant(glm::mat3(m))) > 0.0f)) {
      return Invalid("node_transform.matrix", "singular (zero scale)");
    }
    GS_RETURN_IF_ERROR(CheckPos("node_transform.matrix[3]", glm::vec3(m[3])));
    GS_RETURN_IF_ERROR(
        CheckScale("update.node_transform.matrix.scale",
                   glm::vec3(glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])),
                             glm::length(glm::vec3(m[2])))));
    return absl::OkStatus();
  }
  GS_RETURN_IF_ERROR(CheckPos("node_transform.translation", u.translation));
  GS_RETURN_IF_ERROR(CheckQuat("node_transform.rotation", u.rotation));
  GS_RETURN_IF_ERROR(CheckVec<3>("node_transform.scale", u.scale, "xyz"));
  for (int i = 0; i < 3; ++i) {
    if (u.scale[i] == 0.0f) {
      return Invalid(absl::StrCat("node_transform.scale.", absl::string_view(&"xyz"[i], 1)),
                     "0; scale must be non-zero");
    }
  }
  return CheckScale("update.node_transform.scale", u.scale);
}

absl::Status Check(const Scene& scene, const LightUpdate& u) {
  GS_RETURN_IF_ERROR(
      CheckId("light.light", u.light, LightInstanceNodes(scene).size(), "light instances"));
  if (u.color) {
    GS_RETURN_IF_ERROR(CheckVec<3>("light.color", *u.color, "rgb", 0.0f));
    GS_RETURN_IF_ERROR(CheckAtMost("light.color", MaxComponent(*u.color), kMaxRadiance));
  }
  if (u.intensity) {
    GS_RETURN_IF_ERROR(CheckAtLeast("light.intensity", *u.intensity, 0.0f));
    GS_RETURN_IF_ERROR(CheckAtMost("light.intensity", *u.intensity, kMaxRadiance));
  }
  // colour x intensity against the current values is checked when the
  // update is applied (SceneState::CheckApply).
  if (u.color && u.intensity && MaxComponent(*u.color) * *u.intensity > kMaxRadiance) {
    return Invalid("light.intensity",
                   absl::StrCat(*u.intensity, " x colour ", MaxComponent(*u.color),
                                " exceeds the limit of ", kMaxRadiance));
  }
  if (u.position) GS_RETURN_IF_ERROR(CheckPos("light.position", *u.position));
  if (u.direction) GS_RETURN_IF_ERROR(CheckNonZero("light.direction", *u.direction));
  const float half_pi = std::numbers::pi_v<float> / 2;
  for (const auto& [field, angle] : {std::pair{"light.inner_cone_angle", u.inner_cone_angle},
                                     std::pair{"light.outer_cone_angle", u.outer_cone_angle}}) {
    if (!angle) continue;
    GS_RETURN_IF_ERROR(CheckAtLeast(field, *angle, 0.0f));
    if (*angle > half_pi) return Invalid(field, absl::StrCat(*angle, " exceeds pi/2"));
  }
  // With only one angle given the other is the light's current one, which
  // the render thread holds; it orders the pair when it applies the update.
  if (u.inner_cone_angle && u.outer_cone_angle && *u.inner_cone_angle > *u.outer_cone_angle) {
    return Invalid(
        "light.inner_cone_angle",
        absl::StrCat(*u.inner_cone_angle, " exceeds outer_cone_angle ", *u.outer_cone_angle));
  }
  return absl::OkStatus();
}

absl::Status Check(const Scene& scene, const CameraUpdate& u, uint32_t max_width,
                   uint32_t max_height) {
  if (int(u.look_at.has_value()) + int(u.pose.has_value()) + int(u.scene_camera.has_value()) > 1) {
    return Invalid("camera", "look_at, pose and scene_camera are mutually exclusive");
  }
  if (u.look_at) {
    GS_RETURN_IF_ERROR(CheckPos("camera.look_at.eye", u.look_at->eye));
    GS_RETURN_IF_ERROR(CheckPos("camera.look_at.target", u.look_at->target));
    GS_RETURN_IF_ERROR(CheckNonZero("camera.look_at.up", u.look_at->up));
    const glm::vec3 dir = u.look_at->target - u.look_at->eye;
    if (!(glm::length(dir) > 0.0f)) return Invalid("camera.look_at", "eye equals target");
    if (!(glm::length(glm::cross(glm::normalize(dir), glm::normalize(u.look_at->up))) > 1e-6f)) {
      return Invalid("camera.look_at.up", "parallel to the view direction");
    }
  }
  if (u.pose) {
    GS_RETURN_IF_ERROR(CheckPos("camera.pose.position", u.pose->position));
    GS_RETURN_IF_ERROR(CheckQuat("camera.pose.rotation", u.pose->rotation));
  }
  if (u.scene_camera) {
    GS_RETURN_IF_ERROR(CheckId("camera.scene_camera", *u.scene_camera,
                               CameraInstanceNodes(scene).size(), "camera instances"));
  }
  if (u.yfov_degrees) {
    const float fov = *u.yfov_degrees;
    if (!(fov >= kMinYfovDegrees && fov <= kMaxYfovDegrees)) {
      return Invalid("camera.yfov_degrees", absl::StrCat(fov, " is out of range [", kMinYfovDegrees,
                                                         ", ", kMaxYfovDegrees, "]"));
    }
  }
  if (u.width.has_value() != u.height.has_value()) {
    return Invalid(u.width ? "camera.height" : "camera.width",
                   "missing; width and height are set together");
  }
  if (u.width) {
    if (*u.width < 1 || *u.width > max_width) {
      return Invalid("camera.width",
                     absl::StrCat(*u.width, " is out of range [1, ", max_width, "]"));
    }
    if (*u.height < 1 || *u.height > max_height) {
      return Invalid("camera.height",
                     absl::StrCat(*u.height, " is out of range [1, ", max_height, "]"));
    }
  }
  return absl::OkStatus();
}

absl::Status Check(const Scene& scene, const MaterialUpdate& u) {
  GS_RETURN_IF_ERROR(CheckId("material.material", u.material, scene.materials.size(), "materials"));
  if (u.base_color) {
    GS_RETURN_IF_ERROR(CheckVec<4>("material.base_color", *u.base_color, "rgba", 0.0f));
    for (int i = 0; i < 4; ++i) {
      // An albedo above 1 would create energy.
      if ((*u.base_color)[i] > 1.0f) {
        return Invalid(absl::StrCat("material.base_color.", absl::string_view(&"rgba"[i], 1)),
                       absl::StrCat((*u.base_color)[i], " exceeds 1"));
      }
    }
  }
  if (u.emissive) {
    GS_RETURN_IF_ERROR(CheckVec<3>("material.emissive", *u.emissive, "rgb", 0.0f));
    GS_RETURN_IF_ERROR(CheckAtMost("material.emissive", MaxComponent(*u.emissive), kMaxRadiance));
  }
  if (u.metallic) {
    GS_RETURN_IF_ERROR(CheckAtLeast("material.metallic", *u.metallic, 0.0f));
    GS_RETURN_IF_ERROR(CheckAtMost("material.metallic", *u.metallic, 1.0f));
  }
  if (u.roughness) {
    GS_RETURN_IF_ERROR(CheckAtLeast("material.roughness", *u.roughness, 0.0f));
    GS_RETURN_IF_ERROR(CheckAtMost("material.roughness", *u.roughness, 1.0f));
  }
  if (u.emissive_strength) {
    GS_RETURN_IF_ERROR(CheckAtLeast("material.emissive_strength", *u.emissive_strength, 0.0f));
    GS_RETURN_IF_ERROR(
        CheckAtMost("material.emissive_strength", *u.emissive_strength, kMaxRadiance));
  }
  // factor x strength against the current values: SceneState::CheckApply.
  if (u.emissive && u.emissive_strength &&
      MaxComponent(*u.emissive) * *u.emissive_strength > kMaxRadiance) {
    return Invalid("material.emissive_strength",
                   absl::StrCat(*u.emissive_strength, " x emissive ", MaxComponent(*u.emissive),
                                " exceeds the limit of ", kMaxRadiance, " nits"));
  }
  return absl::OkStatus();
}

absl::Status Check(const Scene& scene, const EnvironmentUpdate& u) {
  if (!scene.environment) return Invalid("environment", "the scene has no environment map");
  if (u.rotation) GS_RETURN_IF_ERROR(CheckFinite("environment.rotation", *u.rotation));
  if (u.intensity) {
    GS_RETURN_IF_ERROR(CheckAtLeast("environment.intensity", *u.intensity, 0.0f));
    GS_RETURN_IF_ERROR(CheckAtMost("environment.intensity", *u.intensity, kMaxRadiance));
    const float brightest = scene.environment->max_radiance;
    if (*u.intensity * brightest > kMaxRadiance) {
      return Invalid("environment.intensity",
                     absl::StrCat(*u.intensity, " x the map's brightest pixel ", brightest,
                                  " exceeds the limit of ", kMaxRadiance, " nits"));
    }
  }
  return absl::OkStatus();
}

absl::Status Check(const Scene& scene, const AnimationUpdate& u) {
  if (u.animation.has_value() == u.name.has_value()) {
    return Invalid("animation", "give exactly one of animation (an index) and name");
  }
  if (u.animation) {
    GS_RETURN_IF_ERROR(
        CheckId("animation.animation", *u.animation, scene.animations.size(), "animations"));
  } else {
    const bool found = std::any_of(scene.animations.begin(), scene.animations.end(),
                                   [&](const Animation& a) { return a.name == *u.name; });
    if (!found) {
      return Invalid("animation.name", absl::StrCat("'", *u.name, "' names none of the scene's ",
                                                    scene.animations.size(), " animations"));
    }
  }
  if (!u.playing && !u.time && !u.speed && !u.loop) {
    return Invalid("animation", "sets none of playing, time, speed, loop");
  }
  if (u.time) {
    GS_RETURN_IF_ERROR(CheckFinite("animation.time", *u.time));
    if (std::abs(*u.time) > kMaxAnimationTime) {
      return Invalid("animation.time",
                     absl::StrCat(*u.time, " exceeds the limit of +-", kMaxAnimationTime, " s"));
    }
  }
  if (u.speed) {
    GS_RETURN_IF_ERROR(CheckFinite("animation.speed", *u.speed));
    if (std::abs(*u.speed) > kMaxAnimationSpeed) {
      return Invalid("animation.speed",
                     absl::StrCat(*u.speed, " exceeds the limit of +-", kMaxAnimationSpeed));
    }
  }
  return absl::OkStatus();
}

absl::Status Check(const Scene& scene, const MorphWeightsUpdate& u) {
  GS_RETURN_IF_ERROR(CheckId("morph_weights.node", u.node, scene.nodes.size(), "nodes"));
  const Node& node = scene.nodes[u.node];
  const size_t targets = node.mesh >= 0 && !scene.meshes[size_t(node.mesh)].primitives.empty()
                             ? scene.meshes[size_t(node.mesh)].primitives.front().targets.size()
                             : 0;
  if (targets == 0) {
    return Invalid("morph_weights.node", absl::StrCat(u.node, " draws no mesh with morph targets"));
  }
  if (u.weights.size() != targets) {
    return Invalid("morph_weights.weights",
                   absl::StrCat(u.weights.size(), " weights for ", targets, " morph targets"));
  }
  for (size_t i = 0; i < u.weights.size(); ++i) {
    const std::string field = absl::StrCat("morph_weights.weights[", i, "]");
    GS_RETURN_IF_ERROR(CheckFinite(field, u.weights[i]));
    if (std::abs(u.weights[i]) > kMaxMorphWeight) {
      return Invalid(field,
                     absl::StrCat(u.weights[i], " exceeds the limit of +-", kMaxMorphWeight));
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status ValidateUpdate(const Scene& scene, const Update& update, uint32_t max_width,
                            uint32_t max_height) {
  return std::visit(
      [&](const auto& change) -> absl::Status {
        if constexpr (std::is_same_v<std::decay_t<decltype(change)>, CameraUpdate>) {
          return Check(scene, change, max_width, max_height);
        } else {
          return Check(scene, change);
        }
      },
      update.change);
}

}  // namespace gistream
