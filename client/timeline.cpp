#include "timeline.h"

#include <algorithm>
#include <map>
#include <memory>
#include <string>

#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>
#include <google/protobuf/util/message_differencer.h>

namespace gistream::client {
namespace {

v1::Vec3 ToProto(const glm::vec3& v) {
  v1::Vec3 out;
  out.set_x(v.x);
  out.set_y(v.y);
  out.set_z(v.z);
  return out;
}

v1::Quat ToProto(const glm::quat& q) {
  v1::Quat out;
  out.set_x(q.x);
  out.set_y(q.y);
  out.set_z(q.z);
  out.set_w(q.w);
  return out;
}

glm::vec3 FromProto(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

// Initial local transform of a node as LoadScene reports it. An unset
// rotation or scale (proto3 default) means identity.
struct Trs {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 scale{1.0f};
};

Trs InitialTrs(const v1::NodeInfo& node) {
  Trs trs;
  trs.translation = FromProto(node.translation());
  if (node.has_rotation()) {
    const v1::Quat& q = node.rotation();
    const glm::quat rotation(q.w(), q.x(), q.y(), q.z());
    if (glm::length(rotation) > 1e-6f) trs.rotation = glm::normalize(rotation);
  }
  if (node.has_scale()) trs.scale = FromProto(node.scale());
  return trs;
}

// Finds `ref` among `items` (NodeInfo, LightInfo or MaterialInfo: each has
// id() and name()). `kind` is "node", "light" or "material".
template <typename Items>
absl::StatusOr<uint32_t> Resolve(const ObjectRef& ref, const Items& items, absl::string_view kind) {
  if (ref.id) {
    for (const auto& item : items) {
      if (item.id() == *ref.id) return *ref.id;
    }
    return absl::InvalidArgumentError(
        absl::StrCat(ref.path, ": the scene has no ", kind, " with id ", *ref.id));
  }
  std::vector<uint32_t> matches;
  std::vector<std::string> names;
  for (const auto& item : items) {
    if (item.name() == ref.name) matches.push_back(item.id());
    if (!item.name().empty()) names.push_back(item.name());
  }
  if (matches.size() == 1) return matches.front();
  if (matches.size() > 1) {
    return absl::InvalidArgumentError(
        absl::StrCat(ref.path, ": ", matches.size(), " ", kind, "s are named \"", ref.name,
                     "\"; name it by id (one of ", absl::StrJoin(matches, ", "), ")"));
  }
  constexpr size_t kMaxListed = 12;
  std::string known = names.empty() ? "none" : "";
  for (size_t i = 0; i < names.size() && i < kMaxListed; ++i) {
    absl::StrAppend(&known, i ? ", " : "", names[i]);
  }
  if (names.size() > kMaxListed) absl::StrAppend(&known, ", ...");
  return absl::InvalidArgumentError(absl::StrCat(ref.path, ": the scene has no ", kind, " named \"",
                                                 ref.name, "\" (", kind, "s: ", known, ")"));
}

const v1::NodeInfo* FindNode(const v1::LoadSceneResponse& scene, uint32_t id) {
  for (const auto& node : scene.nodes()) {
    if (node.id() == id) return &node;
  }
  return nullptr;
}

v1::Update LookAtUpdate(const glm::vec3& eye, const glm::vec3& target,
                        std::optional<float> yfov_degrees) {
  v1::Update update;
  v1::CameraChange* camera = update.mutable_camera();
  v1::LookAt* look_at = camera->mutable_look_at();
  *look_at->mutable_eye() = ToProto(eye);
  *look_at->mutable_target() = ToProto(target);
  *look_at->mutable_up() = ToProto(glm::vec3(0.0f, 1.0f, 0.0f));
  if (yfov_degrees) camera->set_yfov_degrees(*yfov_degrees);
  return update;
}

// Everything that animates one node: its node_path tracks (later ones win
// per field), then its spins, each about its axis relative to the path's
// (or the initial) rotation.
struct NodeAnimation {
  uint32_t node = 0;
  Trs initial;
  std::vector<NodePathTrack> paths;
  std::vector<NodeSpinTrack> spins;

  v1::Update At(int frame) const {
    Trs trs = initial;
    for (const NodePathTrack& path : paths) {
      if (!path.translation.empty()) trs.translation = path.translation.At(frame);
      if (!path.rotation.empty()) trs.rotation = path.rotation.At(frame);
      if (!path.scale.empty()) trs.scale = path.scale.At(frame);
    }
    for (const NodeSpinTrack& spin : spins) {
      const float angle = glm::radians(spin.degrees_per_frame * static_cast<float>(frame));
      trs.rotation = glm::angleAxis(angle, spin.axis) * trs.rotation;
    }
    v1::Update update;
    v1::NodeTransform* transform = update.mutable_node_transform();
    transform->set_node(node);
    *transform->mutable_translation() = ToProto(trs.translation);
    *transform->mutable_rotation() = ToProto(glm::normalize(trs.rotation));
    *transform->mutable_scale() = ToProto(trs.scale);
    return update;
  }
};

v1::Update LightAt(const LightTrack& track, uint32_t light, int frame) {
  v1::Update update;
  v1::LightChange* change = update.mutable_light();
  change->set_light(light);
  if (!track.intensity.empty()) change->set_intensity(track.intensity.At(frame));
  if (!track.color.empty()) *change->mutable_color() = ToProto(track.color.At(frame));
  if (!track.position.empty()) *change->mutable_position() = ToProto(track.position.At(frame));
  if (!track.direction.empty()) {
    // Keys are unit vectors; their blend is renormalized (opposite keys
    // would blend through zero: hold the earlier one instead).
    glm::vec3 direction = track.direction.At(frame);
    if (glm::length(direction) < 1e-6f) direction = track.direction.keys.front().second;
    *change->mutable_direction() = ToProto(glm::normalize(direction));
  }
  if (!track.inner_cone_angle.empty())
    change->set_inner_cone_angle(track.inner_cone_angle.At(frame));
  if (!track.outer_cone_angle.empty())
    change->set_outer_cone_angle(track.outer_cone_angle.At(frame));
  return update;
}

v1::Update MaterialAt(const MaterialTrack& track, uint32_t material, int frame) {
  v1::Update update;
  v1::MaterialChange* change = update.mutable_material();
  change->set_material(material);
  if (!track.base_color.empty()) {
    const glm::vec4 color = track.base_color.At(frame);
    for (int i = 0; i < (track.base_color_rgba ? 4 : 3); ++i) change->add_base_color(color[i]);
  }
  if (!track.emissive.empty()) *change->mutable_emissive() = ToProto(track.emissive.At(frame));
  if (!track.emissive_strength.empty()) {
    change->set_emissive_strength(track.emissive_strength.At(frame));
  }
  if (!track.metallic.empty()) change->set_metallic(track.metallic.At(frame));
  if (!track.roughness.empty()) change->set_roughness(track.roughness.At(frame));
  return update;
}

v1::Update EnvironmentAt(const EnvironmentTrack& track, int frame) {
  v1::Update update;
  v1::EnvironmentChange* change = update.mutable_environment();
  if (!track.rotation.empty()) change->set_rotation(track.rotation.At(frame));
  if (!track.intensity.empty()) change->set_intensity(track.intensity.At(frame));
  return update;
}

}  // namespace

absl::StatusOr<Timeline> Timeline::Build(const Script& script, const v1::LoadSceneResponse& scene) {
  Timeline timeline;
  timeline.frames_ = script.frames;
  const int frames = script.frames;

  // Node tracks are gathered per node; the node's channel sits where its
  // first track does.
  std::map<uint32_t, std::shared_ptr<NodeAnimation>> nodes;
  auto node_animation = [&](const ObjectRef& ref) -> absl::StatusOr<NodeAnimation*> {
    GS_ASSIGN_OR_RETURN(uint32_t id, Resolve(ref, scene.nodes(), "node"));
    std::shared_ptr<NodeAnimation>& animation = nodes[id];
    if (!animation) {
      animation = std::make_shared<NodeAnimation>();
      animation->node = id;
      const v1::NodeInfo* info = FindNode(scene, id);
      GS_CHECK(info != nullptr);  // Resolve found it
      animation->initial = InitialTrs(*info);
      timeline.channels_.push_back([animation](int frame) { return animation->At(frame); });
    }
    return animation.get();
  };

  for (const Track& track : script.tracks) {
    if (const auto* orbit = std::get_if<CameraOrbitTrack>(&track.spec)) {
      timeline.channels_.push_back([orbit = *orbit, frames](int frame) {
        const float t = static_cast<float>(frame) / static_cast<float>(std::max(1, frames - 1));
        const float angle = glm::radians(orbit.start_deg + (orbit.end_deg - orbit.start_deg) * t);
        const glm::vec3 eye(orbit.target.x + orbit.radius * std::cos(angle), orbit.height,
                            orbit.target.z + orbit.radius * std::sin(angle));
        return LookAtUpdate(eye, orbit.target, orbit.yfov_degrees);
      });
    } else if (const auto* camera = std::get_if<CameraPathTrack>(&track.spec)) {
      timeline.channels_.push_back([camera = *camera](int frame) {
        std::optional<float> yfov;
        if (!camera.yfov_degrees.empty()) yfov = camera.yfov_degrees.At(frame);
        return LookAtUpdate(camera.eye.At(frame), camera.target.At(frame), yfov);
      });
    } else if (const auto* path = std::get_if<NodePathTrack>(&track.spec)) {
      GS_ASSIGN_OR_RETURN(NodeAnimation * animation, node_animation(path->node));
      animation->paths.push_back(*path);
    } else if (const auto* spin = std::get_if<NodeSpinTrack>(&track.spec)) {
      GS_ASSIGN_OR_RETURN(NodeAnimation * animation, node_animation(spin->node));
      animation->spins.push_back(*spin);
    } else if (const auto* light = std::get_if<LightTrack>(&track.spec)) {
      GS_ASSIGN_OR_RETURN(uint32_t id, Resolve(light->light, scene.lights(), "light"));
      timeline.channels_.push_back(
          [light = *light, id](int frame) { return LightAt(light, id, frame); });
    } else if (const auto* material = std::get_if<MaterialTrack>(&track.spec)) {
      GS_ASSIGN_OR_RETURN(uint32_t id, Resolve(material->material, scene.materials(), "material"));
      timeline.channels_.push_back(
          [material = *material, id](int frame) { return MaterialAt(material, id, frame); });
    } else if (const auto* environment = std::get_if<EnvironmentTrack>(&track.spec)) {
      timeline.channels_.push_back(
          [environment = *environment](int frame) { return EnvironmentAt(environment, frame); });
    }
  }

  timeline.events_.resize(static_cast<size_t>(frames));
  for (const ScriptEvent& event : script.events) {
    timeline.events_[static_cast<size_t>(event.frame)].push_back(event.update);
  }
  return timeline;
}

std::vector<v1::Update> Timeline::UpdatesForFrame(int frame) const {
  std::vector<v1::Update> updates;
  for (const Channel& channel : channels_) {
    v1::Update update = channel(frame);
    if (frame == 0 ||
        !google::protobuf::util::MessageDifferencer::Equals(update, channel(frame - 1))) {
      updates.push_back(std::move(update));
    }
  }
  if (frame >= 0 && frame < frames_) {
    const auto& events = events_[static_cast<size_t>(frame)];
    updates.insert(updates.end(), events.begin(), events.end());
  }
  return updates;
}

}  // namespace gistream::client
