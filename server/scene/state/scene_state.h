// The mutable, versioned state of a loaded scene: node transforms, light
// instances, materials, environment. Owned by the render thread. Every
// applied update bumps the version and records what kind of thing changed,
// so a solver that last saw version v asks ChangesSince(v) and runs only the
// stages that change needs.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "scene/scene.h"
#include "scene/updates.h"
#include "util/status.h"

namespace gistream {

// Playback of one glTF animation on this scene's clock.
struct AnimationPlayback {
  bool active = false;   // played or seeked at least once: its pose applies
  bool playing = false;  // the clock advances it
  bool loop = true;      // wraps at the end; else stops there
  float speed = 1.0f;
  double time = 0.0;  // seconds, on the animation's keys
};

struct LightInstance {
  int node = -1;
  Light light;  // current parameters
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // world, the way it shines
};

class SceneState {
 public:
  explicit SceneState(std::shared_ptr<const Scene> scene);

  const Scene& scene() const { return *scene_; }
  uint64_t version() const { return version_; }
  // Distinct for every SceneState this process creates (an address may be
  // reused after one is freed; this is not): with version(), a key for
  // what is derived from the state and cached.
  uint64_t serial() const { return serial_.value; }

  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<glm::mat4>& world() const { return world_; }
  const std::vector<LightInstance>& lights() const { return lights_; }
  const std::vector<Material>& materials() const { return materials_; }
  float environment_intensity() const { return env_intensity_; }
  float environment_rotation() const { return env_rotation_; }
  const std::vector<AnimationPlayback>& animations() const { return playback_; }

  // The mesh node `node` draws as currently posed: for a node whose mesh
  // deforms (a skin, morph targets), its copy morphed and skinned by
  // scene/state/deform.h's DeformPrimitive (positions, normals and bounds in the
  // node's local space, as the scene's); else the scene's own mesh.
  const Mesh& NodeMesh(size_t node) const;
  // Whether `node` draws a mesh that deforms (skinned, or with morph targets).
  bool Deforms(size_t node) const { return node < posed_.size() && posed_[node] != nullptr; }
  // Nodes that draw deforming meshes, in node order.
  const std::vector<int>& deforming_nodes() const { return deforming_; }

  // Advances the playing animations by `seconds` of the scene's clock
  // (x each one's speed), poses their nodes and returns what changed;
  // bumps the version unless nothing did.
  ChangeMask Advance(double seconds);

  // Applies a validated scene update (not camera updates) and returns what
  // changed; bumps the version unless nothing changed.
  ChangeMask Apply(const Change& change);

  // INVALID_ARGUMENT when applying the (validated) `change` would break a
  // magnitude limit of scene/magnitude_limits.h that depends on the current
  // state: a world-space position or scale through the node hierarchy,
  // colour x intensity, emissive factor x strength, environment intensity x
  // its brightest pixel. The state is left unchanged.
  absl::Status CheckApply(const Change& change) const;
  // The same limits over the whole current state (import's check).
  absl::Status CheckMagnitudes(const std::string& prefix) const;

  // Union of the changes after `version`; kChangeAll when the log no longer
  // reaches back that far.
  ChangeMask ChangesSince(uint64_t version) const;

 private:
  void Recompute();
  ChangeMask SubtreeKinds(int node) const;
  void Record(ChangeMask mask);
  // Samples every active animation into nodes_ (scene/state/animation.h);
  // returns what the posed nodes carry.
  ChangeMask PoseAnimations();
  // Re-deforms every deforming node's mesh from nodes_ and world_.
  void Redeform();
  ChangeMask ApplyAnimation(const AnimationUpdate& update);
  ChangeMask ApplyMorphWeights(const MorphWeightsUpdate& update);

  std::shared_ptr<const Scene> scene_;
  std::vector<Node> nodes_;
  std::vector<glm::mat4> world_;
  std::vector<int> light_nodes_;
  std::vector<LightInstance> lights_;
  std::vector<Material> materials_;
  float env_intensity_ = 1.0f;
  float env_rotation_ = 0.0f;
  std::vector<AnimationPlayback> playback_;  // per scene animation
  std::vector<bool> joint_;                  // per node: a joint of some skin
  // Per node: its posed mesh when it deforms, else null. Copied on write,
  // so copies of the state (CheckApply's trial) share them until they change.
  std::vector<std::shared_ptr<Mesh>> posed_;
  std::vector<int> deforming_;
  bool deform_ = true;  // false on CheckApply's trial copy (it checks nodes only)
  uint64_t version_ = 1;
  // A copy (a trial state, CheckUpdate) gets its own serial.
  struct Serial {
    uint64_t value;
    Serial();
    Serial(const Serial&) : Serial() {}
    Serial& operator=(const Serial&) {
      value = Serial().value;
      return *this;
    }
  };
  Serial serial_;
  std::deque<std::pair<uint64_t, ChangeMask>> log_;  // (version, what changed)
};

}  // namespace gistream
