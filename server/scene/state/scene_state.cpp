#include "scene/state/scene_state.h"

#include <atomic>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/matrix_decompose.hpp>
#include <glm/gtx/quaternion.hpp>

#include "scene/state/deform.h"
#include "scene/magnitude_limits.h"

namespace gistream {
namespace {
constexpr size_t kLogLength = 256;

// Rotation that turns -Z into `dir` (unit).
glm::quat RotationTowards(const glm::vec3& dir) {
  const glm::vec3 from(0.0f, 0.0f, -1.0f);
  const float d = glm::dot(from, dir);
  if (d < -0.999999f) return glm::angleAxis(glm::pi<float>(), glm::vec3(0.0f, 1.0f, 0.0f));
  return glm::rotation(from, dir);
}
}  // namespace

SceneState::Serial::Serial() {
  static std::atomic<uint64_t> next{1};
  value = next.fetch_add(1, std::memory_order_relaxed);
}

SceneState::SceneState(std::shared_ptr<const Scene> scene)
    : scene_(std::move(scene)),
      nodes_(scene_->nodes),
      light_nodes_(LightInstanceNodes(*scene_)),
      materials_(scene_->materials) {
  if (scene_->environment) {
    env_intensity_ = scene_->environment->intensity;
    env_rotation_ = scene_->environment->rotation;
  }
  playback_.resize(scene_->animations.size());
  joint_.assign(nodes_.size(), false);
  for (const Skin& skin : scene_->skins) {
    for (int j : skin.joints) joint_[size_t(j)] = true;
  }
  posed_.resize(nodes_.size());
  for (size_t n = 0; n < nodes_.size(); ++n) {
    if (!NodeMeshDeforms(*scene_, n)) continue;  // (its copy counted by CountSceneBytes)
    posed_[n] = std::make_shared<Mesh>(scene_->meshes[size_t(nodes_[n].mesh)]);
    deforming_.push_back(int(n));
  }
  lights_.resize(light_nodes_.size());
  for (size_t i = 0; i < light_nodes_.size(); ++i) {
    lights_[i].node = light_nodes_[i];
    lights_[i].light = scene_->lights[size_t(nodes_[size_t(light_nodes_[i])].light)];
  }
  Recompute();
  Redeform();
}

void SceneState::Recompute() {
  world_ = WorldMatrices(*scene_, nodes_);
  for (LightInstance& l : lights_) {
    const glm::mat4& m = world_[size_t(l.node)];
    l.position = glm::vec3(m[3]);
    const glm::vec3 dir = -glm::vec3(m[2]);
    const float len = glm::length(dir);
    l.direction = len > 0.0f ? dir / len : glm::vec3(0.0f, 0.0f, -1.0f);
  }
}

ChangeMask SceneState::SubtreeKinds(int node) const {
  ChangeMask mask = kChangeNone;
  std::vector<int> stack{node};
  while (!stack.empty()) {
    const size_t index = size_t(stack.back());
    const Node& n = nodes_[index];
    stack.pop_back();
    if (n.mesh >= 0) mask |= kChangeGeometry;
    if (n.light >= 0) mask |= kChangeLights;
    // A joint reshapes the meshes its skin deforms; a skinned mesh's own
    // node changes its deformed local positions (glTF 2.0 3.7.3.3).
    if (joint_[index] || (n.skin >= 0 && n.mesh >= 0)) mask |= kChangeDeformation;
    for (int c : n.children) stack.push_back(c);
  }
  return mask;
}

void SceneState::Record(ChangeMask mask) {
  if (mask == kChangeNone) return;
  ++version_;
  log_.emplace_back(version_, mask);
  if (log_.size() > kLogLength) log_.pop_front();
}

ChangeMask SceneState::ChangesSince(uint64_t version) const {
  if (version >= version_) return kChangeNone;
  if (log_.empty() || log_.front().first > version + 1) return kChangeAll;
  ChangeMask mask = kChangeNone;
  for (const auto& [v, m] : log_) {
    if (v > version) mask |= m;
  }
  return mask;
}

ChangeMask SceneState::Apply(const Change& change) {
  ChangeMask mask = kChangeNone;
  if (const auto* t = std::get_if<NodeTransformUpdate>(&change)) {
    Node& node = nodes_[t->node];
    if (t->matrix) {
      glm::vec3 skew;
      glm::vec4 perspective;
      glm::decompose(*t->matrix, node.scale, node.rotation, node.translation, skew, perspective);
    } else {
      node.translation = t->translation;
      node.rotation = glm::normalize(t->rotation);
      node.scale = t->scale;
    }
    mask = SubtreeKinds(int(t->node));
    Recompute();
    if (mask & kChangeDeformation) Redeform();
  } else if (const auto* l = std::get_if<LightUpdate>(&change)) {
    LightInstance& inst = lights_[l->light];
    if (l->color) inst.light.color = *l->color;
    if (l->intensity) inst.light.intensity = *l->intensity;
    if (l->inner_cone_angle) inst.light.inner_cone_angle = *l->inner_cone_angle;
    if (l->outer_cone_angle) inst.light.outer_cone_angle = *l->outer_cone_angle;
    if (l->position || l->direction) {
      // Position and direction are world space: write them into the light
      // node's local transform so the scene graph stays the one truth.
      Node& node = nodes_[size_t(inst.node)];
      const glm::mat4 parent = node.parent >= 0 ? world_[size_t(node.parent)] : glm::mat4(1.0f);
      const glm::mat4 inv_parent = glm::inverse(parent);
      if (l->position) node.translation = glm::vec3(inv_parent * glm::vec4(*l->position, 1.0f));
      if (l->direction) {
        glm::vec3 local_dir = glm::mat3(inv_parent) * glm::normalize(*l->direction);
        node.rotation = RotationTowards(glm::normalize(local_dir));
      }
      mask |= SubtreeKinds(inst.node);
      Recompute();
      if (mask & kChangeDeformation) Redeform();
    }
    mask |= kChangeLights;
  } else if (const auto* m = std::get_if<MaterialUpdate>(&change)) {
    Material& mat = materials_[m->material];
    if (m->base_color) {
      mat.base_color_factor = *m->base_color;
      mask |= kChangeMaterials;
    }
    if (m->metallic) {
      mat.metallic_factor = *m->metallic;
      mask |= kChangeMaterials;
    }
    if (m->roughness) {
      mat.roughness_factor = *m->roughness;
      mask |= kChangeMaterials;
    }
    if (m->emissive) {
      mat.emissive_factor = *m->emissive;
      mask |= kChangeEmission;
    }
    if (m->emissive_strength) {
      mat.emissive_strength = *m->emissive_strength;
      mask |= kChangeEmission;
    }
  } else if (const auto* e = std::get_if<EnvironmentUpdate>(&change)) {
    if (e->intensity) env_intensity_ = *e->intensity;
    if (e->rotation) env_rotation_ = *e->rotation;
    if (scene_->environment) mask |= kChangeEnvironment;
  } else if (const auto* a = std::get_if<AnimationUpdate>(&change)) {
    mask = ApplyAnimation(*a);
  } else if (const auto* w = std::get_if<MorphWeightsUpdate>(&change)) {
    mask = ApplyMorphWeights(*w);
  }
  Record(mask);
  return mask;
}

absl::Status SceneState::CheckMagnitudes(const std::string& prefix) const {
  GS_RETURN_IF_ERROR(CheckWorldExtent(*scene_, nodes_, world_, prefix));
  for (size_t i = 0; i < lights_.size(); ++i) {
    const float strength = MaxLightStrength(lights_[i].light);
    if (!(strength <= kMaxRadiance)) {
      return absl::InvalidArgumentError(absl::StrCat(prefix, "lights[", i, "]: colour x intensity ",
                                                     strength, " exceeds the limit of ",
                                                     kMaxRadiance));
    }
  }
  for (size_t i = 0; i < materials_.size(); ++i) {
    const float emission = MaxEmission(materials_[i]);
    if (!(emission <= kMaxRadiance)) {
      return absl::InvalidArgumentError(
          absl::StrCat(prefix, "materials[", i, "]: emissive factor x strength ", emission,
                       " exceeds the limit of ", kMaxRadiance, " nits"));
    }
  }
  if (scene_->environment) {
    const float env = env_intensity_ * scene_->environment->max_radiance;
    if (!(env <= kMaxRadiance)) {
      return absl::InvalidArgumentError(
          absl::StrCat(prefix, "environment: intensity x brightest pixel ", env,
                       " exceeds the limit of ", kMaxRadiance, " nits"));
    }
  }
  return absl::OkStatus();
}

absl::Status SceneState::CheckApply(const Change& change) const {
  // The common cases touch one light, material or the environment: check
  // just that, without copying the state.
  if (const auto* m = std::get_if<MaterialUpdate>(&change)) {
    Material mat = materials_[m->material];
    if (m->emissive) mat.emissive_factor = *m->emissive;
    if (m->emissive_strength) mat.emissive_strength = *m->emissive_strength;
    const float emission = MaxEmission(mat);
    if (!(emission <= kMaxRadiance)) {
      return absl::InvalidArgumentError(absl::StrCat(
          "update.material: after it, materials[", m->material, "]: emissive factor x strength ",
          emission, " exceeds the limit of ", kMaxRadiance, " nits"));
    }
    return absl::OkStatus();
  }
  if (const auto* e = std::get_if<EnvironmentUpdate>(&change)) {
    const float env = (e->intensity ? *e->intensity : env_intensity_) *
                      (scene_->environment ? scene_->environment->max_radiance : 0.0f);
    if (!(env <= kMaxRadiance)) {
      return absl::InvalidArgumentError(
          absl::StrCat("update.environment: after it, environment: intensity x brightest pixel ",
                       env, " exceeds the limit of ", kMaxRadiance, " nits"));
    }
    return absl::OkStatus();
  }
  // Animation keys were held to the import's limits; morph weights to
  // validation's.
  if (std::holds_alternative<AnimationUpdate>(change) ||
      std::holds_alternative<MorphWeightsUpdate>(change)) {
    return absl::OkStatus();
  }
  const auto* l = std::get_if<LightUpdate>(&change);
  if (l != nullptr && !l->position && !l->direction) {
    Light light = lights_[l->light].light;
    if (l->color) light.color = *l->color;
    if (l->intensity) light.intensity = *l->intensity;
    const float strength = MaxLightStrength(light);
    if (!(strength <= kMaxRadiance)) {
      return absl::InvalidArgumentError(absl::StrCat("update.light: after it, lights[", l->light,
                                                     "]: colour x intensity ", strength,
                                                     " exceeds the limit of ", kMaxRadiance));
    }
    return absl::OkStatus();
  }
  // A transform (a node's, or a light's position/direction) moves a
  // subtree: recompute and check the whole state on a copy.
  SceneState trial = *this;
  trial.deform_ = false;
  trial.Apply(change);
  return trial.CheckMagnitudes(
      absl::StrCat("update.", l != nullptr ? "light" : "node_transform", ": after it, "));
}

}  // namespace gistream
