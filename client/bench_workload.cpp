#include "bench_workload.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <absl/strings/numbers.h>
#include <absl/strings/str_cat.h>
#include <absl/strings/match.h>

#include "script.h"

namespace gistream::client {
namespace {

// Motions are periodic in the tick: small enough that the picture stays the
// scene's (the camera swings ±15° about its start, objects move by 3 % of
// the scene's diagonal), large enough that every update changes the image.
constexpr double kOrbitSwingRad = 15.0 * std::numbers::pi / 180.0;
constexpr double kOrbitPeriodTicks = 60.0;
constexpr double kMotionPeriodTicks = 40.0;
constexpr float kMotionFraction = 0.03f;
constexpr double kIntensitySwing = 0.3;  // intensity × (1 ± 0.3)
// The animation workload seeks the scene's animation 1/30 s further each
// tick (looped by the server): the animation at 30 ticks a second, and the
// same poses in every run whatever the update rate.
constexpr double kAnimationSecondsPerTick = 1.0 / 30.0;

double Phase(uint64_t tick, double period) {
  return std::sin(2.0 * std::numbers::pi * double(tick % uint64_t(period)) / period);
}

v1::Vec3 Vec(float x, float y, float z) {
  v1::Vec3 v;
  v.set_x(x);
  v.set_y(y);
  v.set_z(z);
  return v;
}

bool IsEmissive(const v1::MaterialInfo& m) {
  return m.emissive().x() > 0.0f || m.emissive().y() > 0.0f || m.emissive().z() > 0.0f;
}

// The node `object` moves: the one named or numbered `wanted`, else the
// first whose name says it is a block or box, else the last mesh node.
absl::StatusOr<v1::NodeInfo> PickNode(const v1::LoadSceneResponse& scene,
                                      const std::string& wanted) {
  const v1::NodeInfo* blocky = nullptr;
  const v1::NodeInfo* last_mesh = nullptr;
  uint32_t id = 0;
  const bool by_id = !wanted.empty() && absl::SimpleAtoi(wanted, &id);
  for (const v1::NodeInfo& node : scene.nodes()) {
    if (!wanted.empty()) {
      if ((by_id && node.id() == id) || node.name() == wanted) return node;
      continue;
    }
    if (node.mesh() < 0) continue;
    last_mesh = &node;
    if (blocky == nullptr &&
        (absl::StrContains(node.name(), "block") || absl::StrContains(node.name(), "box"))) {
      blocky = &node;
    }
  }
  const v1::NodeInfo* pick = blocky != nullptr ? blocky : last_mesh;
  if (!wanted.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat("--node: the scene has no node \"", wanted, "\""));
  }
  if (pick == nullptr) {
    return absl::FailedPreconditionError("workload object: the scene has no node with a mesh");
  }
  return *pick;
}

}  // namespace

absl::StatusOr<WorkloadSpec> ParseWorkload(const std::string& text) {
  WorkloadSpec spec;
  if (text == "orbit")
    spec.kind = WorkloadKind::kOrbit;
  else if (text == "light")
    spec.kind = WorkloadKind::kLight;
  else if (text == "object")
    spec.kind = WorkloadKind::kObject;
  else if (text == "mixed")
    spec.kind = WorkloadKind::kMixed;
  else if (text == "animation")
    spec.kind = WorkloadKind::kAnimation;
  else if (absl::EndsWith(text, ".json")) {
    spec.kind = WorkloadKind::kScript;
    spec.script = text;
  } else {
    return absl::InvalidArgumentError(
        absl::StrCat("--workload: \"", text,
                     "\" is not orbit, light, object, mixed, animation or a script .json file"));
  }
  return spec;
}

std::string WorkloadName(const WorkloadSpec& spec) {
  switch (spec.kind) {
    case WorkloadKind::kOrbit: return "orbit";
    case WorkloadKind::kLight: return "light";
    case WorkloadKind::kObject: return "object";
    case WorkloadKind::kMixed: return "mixed";
    case WorkloadKind::kAnimation: return "animation";
    case WorkloadKind::kScript: return spec.script.filename().string();
  }
  return "?";
}

absl::Status Workload::SetUpScript(const std::filesystem::path& script_file,
                                   const v1::LoadSceneResponse& scene) {
  GS_ASSIGN_OR_RETURN(Script script, LoadScriptFile(script_file));
  GS_ASSIGN_OR_RETURN(Timeline timeline, Timeline::Build(script, scene));
  if (timeline.frames() <= 0) {
    return absl::InvalidArgumentError(absl::StrCat(script_file.string(), ": frames: must be > 0"));
  }
  timeline_ = std::move(timeline);
  description_ = absl::StrCat("script ", script_file.filename().string(), " (", timeline_->frames(),
                              " frames, looped)");
  return absl::OkStatus();
}

absl::Status Workload::SetUpAnimation(const v1::LoadSceneResponse& scene) {
  if (scene.animations_size() == 0) {
    return absl::FailedPreconditionError("workload animation: the scene has no animation");
  }
  animation_ = scene.animations(0);
  description_ =
      absl::StrCat("animation ", animation_->id(), " (", animation_->name(), ", ",
                   animation_->end() - animation_->start(), " s) seeked 1/30 s a tick, looped");
  return absl::OkStatus();
}

std::string Workload::SetUpOrbit(const v1::LoadSceneResponse& scene, float diagonal) {
  // Around the vertical axis through the scene's centre, starting at the
  // scene camera (or in front of the scene when it has none).
  float ex = center_[0], ey = center_[1], ez = center_[2] + 1.5f * diagonal;
  if (scene.cameras_size() > 0) {
    const v1::Vec3& p = scene.cameras(0).position();
    ex = p.x(), ey = p.y(), ez = p.z();
  }
  height_ = ey;
  radius_ = std::hypot(ex - center_[0], ez - center_[2]);
  if (!(radius_ > 1e-6f)) radius_ = std::max(diagonal, 1e-3f);
  start_rad_ = float(std::atan2(ez - center_[2], ex - center_[0]));
  return "camera orbit ±15°";
}

absl::StatusOr<std::string> Workload::SetUpLight(const v1::LoadSceneResponse& scene) {
  if (scene.lights_size() > 0) {
    light_ = scene.lights(0);
    return absl::StrCat("light ", light_->id(), " (", light_->name(), ") intensity",
                        light_->type() == v1::LIGHT_TYPE_DIRECTIONAL ? "" : " and position");
  }
  for (const v1::MaterialInfo& m : scene.materials()) {
    if (IsEmissive(m)) {
      emitter_ = m;
      break;
    }
  }
  if (!emitter_) {
    return absl::FailedPreconditionError(
        "workload light: the scene has no punctual light and no emissive material");
  }
  return absl::StrCat("emitter material ", emitter_->id(), " (", emitter_->name(), ") strength");
}

absl::StatusOr<Workload> Workload::Create(const WorkloadSpec& spec,
                                          const v1::LoadSceneResponse& scene) {
  Workload w;
  w.kind_ = spec.kind;
  const v1::Vec3& lo = scene.bounds().min();
  const v1::Vec3& hi = scene.bounds().max();
  w.center_[0] = 0.5f * (lo.x() + hi.x());
  w.center_[1] = 0.5f * (lo.y() + hi.y());
  w.center_[2] = 0.5f * (lo.z() + hi.z());
  const float dx = hi.x() - lo.x(), dy = hi.y() - lo.y(), dz = hi.z() - lo.z();
  const float diagonal = std::sqrt(dx * dx + dy * dy + dz * dz);
  w.amplitude_ = std::max(kMotionFraction * diagonal, 1e-4f);
  if (spec.kind == WorkloadKind::kScript) {
    GS_RETURN_IF_ERROR(w.SetUpScript(spec.script, scene));
    return w;
  }
  if (spec.kind == WorkloadKind::kAnimation) {
    GS_RETURN_IF_ERROR(w.SetUpAnimation(scene));
    return w;
  }
  const bool mixed = spec.kind == WorkloadKind::kMixed;
  std::vector<std::string> parts;
  if (spec.kind == WorkloadKind::kOrbit || mixed) parts.push_back(w.SetUpOrbit(scene, diagonal));
  if (spec.kind == WorkloadKind::kLight || mixed) {
    GS_ASSIGN_OR_RETURN(std::string part, w.SetUpLight(scene));
    parts.push_back(std::move(part));
  }
  if (spec.kind == WorkloadKind::kObject || mixed) {
    GS_ASSIGN_OR_RETURN(v1::NodeInfo node, PickNode(scene, spec.node));
    w.node_ = std::move(node);
    parts.push_back(absl::StrCat("node ", w.node_->id(), " (", w.node_->name(), ") translation"));
  }
  for (size_t i = 0; i < parts.size(); ++i)
    absl::StrAppend(&w.description_, i ? ", " : "", parts[i]);
  return w;
}

v1::Update Workload::Orbit(uint64_t tick) const {
  const double angle = start_rad_ + kOrbitSwingRad * Phase(tick, kOrbitPeriodTicks);
  v1::Update u;
  v1::LookAt* look = u.mutable_camera()->mutable_look_at();
  *look->mutable_eye() = Vec(center_[0] + radius_ * float(std::cos(angle)), height_,
                             center_[2] + radius_ * float(std::sin(angle)));
  *look->mutable_target() = Vec(center_[0], height_, center_[2]);
  *look->mutable_up() = Vec(0, 1, 0);
  return u;
}

v1::Update Workload::Light(uint64_t tick) const {
  const float scale = float(1.0 + kIntensitySwing * Phase(tick, kMotionPeriodTicks));
  v1::Update u;
  if (light_) {
    v1::LightChange* change = u.mutable_light();
    change->set_light(light_->id());
    change->set_intensity(light_->intensity() * scale);
    if (light_->type() != v1::LIGHT_TYPE_DIRECTIONAL) {
      const float offset = amplitude_ * float(Phase(tick + 10, kMotionPeriodTicks));
      const v1::Vec3& p = light_->position();
      *change->mutable_position() = Vec(p.x() + offset, p.y(), p.z());
    }
    return u;
  }
  // MaterialInfo.emissive is factor × strength: send a factor in [0, 1]
  // and the strength that restores the product, scaled.
  const v1::Vec3& e = emitter_->emissive();
  const float peak = std::max({e.x(), e.y(), e.z()});
  v1::MaterialChange* change = u.mutable_material();
  change->set_material(emitter_->id());
  *change->mutable_emissive() = Vec(e.x() / peak, e.y() / peak, e.z() / peak);
  change->set_emissive_strength(peak * scale);
  return u;
}

v1::Update Workload::Object(uint64_t tick) const {
  const float offset = amplitude_ * float(Phase(tick, kMotionPeriodTicks));
  v1::Update u;
  v1::NodeTransform* t = u.mutable_node_transform();
  t->set_node(node_->id());
  const v1::Vec3& p = node_->translation();
  *t->mutable_translation() = Vec(p.x() + offset, p.y(), p.z());
  if (node_->has_rotation())
    *t->mutable_rotation() = node_->rotation();
  else
    t->mutable_rotation()->set_w(1.0f);
  if (node_->has_scale())
    *t->mutable_scale() = node_->scale();
  else
    *t->mutable_scale() = Vec(1, 1, 1);
  return u;
}

v1::Update Workload::Animation(uint64_t tick) const {
  v1::Update u;
  v1::AnimationChange* change = u.mutable_animation();
  change->set_animation(animation_->id());
  change->set_playing(false);  // the ticks are the clock: every run sees the same poses
  change->set_time(float(double(animation_->start()) + double(tick) * kAnimationSecondsPerTick));
  return u;
}

std::vector<v1::Update> Workload::UpdatesForTick(uint64_t tick) const {
  switch (kind_) {
    case WorkloadKind::kOrbit: return {Orbit(tick)};
    case WorkloadKind::kLight: return {Light(tick)};
    case WorkloadKind::kObject: return {Object(tick)};
    case WorkloadKind::kAnimation: return {Animation(tick)};
    case WorkloadKind::kMixed: {
      // One kind per tick, in turn; each advances on its own tick count.
      const uint64_t own = tick / 3;
      switch (tick % 3) {
        case 0: return {Orbit(own)};
        case 1: return {Light(own)};
        default: return {Object(own)};
      }
    }
    case WorkloadKind::kScript:
      return timeline_->UpdatesForFrame(int(tick % uint64_t(timeline_->frames())));
  }
  return {};
}

}  // namespace gistream::client
