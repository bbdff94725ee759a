// The updates a `gistream bench` session sends, tick by tick, derived from
// the loaded scene: orbit (camera only), light (a light's or an emitter's
// intensity, and a punctual light's position), object (a mesh node moves),
// mixed (the three in turn), animation (the scene's own glTF animation,
// sampled tick by tick), or a script file's timeline. Deterministic in
// the tick number, so every session and every run sends the same sequence.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "gistream/v1/gistream.pb.h"
#include "timeline.h"
#include "util/status.h"

namespace gistream::client {

enum class WorkloadKind { kOrbit, kLight, kObject, kMixed, kAnimation, kScript };

struct WorkloadSpec {
  WorkloadKind kind = WorkloadKind::kOrbit;
  std::filesystem::path script;  // kScript
  std::string node;              // kObject/kMixed: node name or id; empty: pick one
};

// "orbit", "light", "object", "mixed", "animation", or a path to a script
// JSON file.
absl::StatusOr<WorkloadSpec> ParseWorkload(const std::string& text);
std::string WorkloadName(const WorkloadSpec& spec);

class Workload {
 public:
  // FAILED_PRECONDITION when the scene has nothing the workload can change
  // (no light or emitter for `light`, no mesh node for `object`, no
  // animation for `animation`).
  static absl::StatusOr<Workload> Create(const WorkloadSpec& spec,
                                         const v1::LoadSceneResponse& scene);

  // The updates of tick `tick` (seq left 0); may be empty for a script
  // frame that changes nothing.
  std::vector<v1::Update> UpdatesForTick(uint64_t tick) const;
  // What is being changed, for the report: "camera orbit", "light 0 (lamp)".
  const std::string& description() const { return description_; }

 private:
  // Create's parts: a script's timeline, the scene's first animation, the
  // camera orbit around the scene centre, the light (or emitter) that is
  // dimmed; each returns what it adds to the description.
  absl::Status SetUpScript(const std::filesystem::path& script, const v1::LoadSceneResponse& scene);
  absl::Status SetUpAnimation(const v1::LoadSceneResponse& scene);
  std::string SetUpOrbit(const v1::LoadSceneResponse& scene, float diagonal);
  absl::StatusOr<std::string> SetUpLight(const v1::LoadSceneResponse& scene);
  v1::Update Orbit(uint64_t tick) const;
  v1::Update Light(uint64_t tick) const;
  v1::Update Object(uint64_t tick) const;
  v1::Update Animation(uint64_t tick) const;

  WorkloadKind kind_ = WorkloadKind::kOrbit;
  std::string description_;
  // orbit
  float center_[3] = {0, 0, 0};
  float radius_ = 1.0f, height_ = 0.0f, start_rad_ = 0.0f;
  // light: a punctual light, else an emissive material
  std::optional<v1::LightInfo> light_;
  std::optional<v1::MaterialInfo> emitter_;
  float amplitude_ = 0.01f;  // of positional motion, metres
  // object
  std::optional<v1::NodeInfo> node_;
  // animation
  std::optional<v1::AnimationInfo> animation_;
  std::optional<Timeline> timeline_;
};

}  // namespace gistream::client
