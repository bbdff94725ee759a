// SceneState's animation clock and deformed meshes: playback of the glTF
// animations (scene/state/animation.h samples them), morph weights set by
// clients, and the posed copies of deforming meshes (scene/state/deform.h, the
// one CPU implementation the GPU pass is tested against).
#include <algorithm>
#include <cmath>

#include "scene/state/animation.h"
#include "scene/state/deform.h"
#include "scene/state/scene_state.h"

namespace gistream {
namespace {

// Time on an animation's keys after moving to `t`: wrapped into
// [start, end) when looping, else clamped to [start, end].
double PlaybackTime(const Animation& a, double t, bool loop) {
  const double start = a.start, end = a.end;
  if (!(end > start)) return start;
  if (!loop) return std::clamp(t, start, end);
  const double length = end - start;
  double u = std::fmod(t - start, length);
  if (u < 0.0) u += length;
  return start + u;
}

}  // namespace

const Mesh& SceneState::NodeMesh(size_t node) const {
  if (Deforms(node)) return *posed_[node];
  return scene_->meshes[size_t(nodes_[node].mesh)];
}

void SceneState::Redeform() {
  if (!deform_) return;
  std::vector<glm::vec3> positions, normals;
  for (int n : deforming_) {
    std::shared_ptr<Mesh>& posed = posed_[size_t(n)];
    if (posed.use_count() > 1) posed = std::make_shared<Mesh>(*posed);  // copy on write
    const Node& node = nodes_[size_t(n)];
    const Mesh& rest = scene_->meshes[size_t(node.mesh)];
    const std::vector<glm::mat4> joints =
        node.skin >= 0 ? JointMatrices(scene_->skins[size_t(node.skin)], world_, n)
                       : std::vector<glm::mat4>();
    const std::span<const float> weights = MorphWeights(*scene_, node);
    for (size_t p = 0; p < rest.primitives.size(); ++p) {
      Primitive& out = posed->primitives[p];
      DeformPrimitive(rest.primitives[p], weights, joints, &out.positions, &out.normals);
      out.bounds = Bounds();
      for (const glm::vec3& v : out.positions) out.bounds.Extend(v);
    }
  }
}

ChangeMask SceneState::PoseAnimations() {
  ChangeMask mask = kChangeNone;
  for (size_t i = 0; i < playback_.size(); ++i) {
    if (!playback_[i].active) continue;
    const std::vector<NodeOverride> overrides =
        SampleAnimation(scene_->animations[i], float(playback_[i].time), AnimationTime::kClamp);
    ApplyOverrides(overrides, &nodes_);
    for (const NodeOverride& o : overrides) {
      if (o.translation || o.rotation || o.scale) mask |= SubtreeKinds(o.node);
      if (!o.weights.empty() && Deforms(size_t(o.node))) mask |= kChangeDeformation;
    }
  }
  Recompute();
  if (mask & kChangeDeformation) Redeform();
  return mask;
}

ChangeMask SceneState::ApplyAnimation(const AnimationUpdate& u) {
  size_t index = u.animation.value_or(0);
  if (u.name) {
    const auto& all = scene_->animations;
    index = size_t(std::find_if(all.begin(), all.end(),
                                [&](const Animation& a) { return a.name == *u.name; }) -
                   all.begin());
  }
  AnimationPlayback& p = playback_[index];
  const Animation& animation = scene_->animations[index];
  if (u.speed) p.speed = *u.speed;
  if (u.loop) p.loop = *u.loop;
  if (u.playing) p.playing = *u.playing;
  const bool was_active = p.active;
  if (u.time) p.time = PlaybackTime(animation, *u.time, p.loop);
  if (u.time || (u.playing && *u.playing)) p.active = true;
  // Only a seek or the first play moves anything; the speed, looping and a
  // pause take effect on the clock.
  if (!u.time && was_active == p.active) return kChangeNone;
  return PoseAnimations();
}

ChangeMask SceneState::ApplyMorphWeights(const MorphWeightsUpdate& u) {
  nodes_[u.node].weights = u.weights;
  Redeform();
  return kChangeDeformation;
}

ChangeMask SceneState::Advance(double seconds) {
  if (!(seconds > 0.0)) return kChangeNone;
  bool moved = false;
  for (size_t i = 0; i < playback_.size(); ++i) {
    AnimationPlayback& p = playback_[i];
    if (!p.active || !p.playing) continue;
    const double t =
        PlaybackTime(scene_->animations[i], p.time + seconds * double(p.speed), p.loop);
    if (t != p.time) moved = true;
    p.time = t;
  }
  if (!moved) return kChangeNone;
  const ChangeMask mask = PoseAnimations();
  Record(mask);
  return mask;
}

}  // namespace gistream
