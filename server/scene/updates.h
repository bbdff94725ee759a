// Domain form of the updates clients push. The service layer translates
// protobuf into these; validation (ids, NaN/Inf, ranges) happens in
// scene/state/validate_update.h before anything reaches the render thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace gistream {

struct NodeTransformUpdate {
  uint32_t node = 0;
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 scale{1.0f};
  std::optional<glm::mat4> matrix;  // overrides TRS when set
};

struct LightUpdate {
  uint32_t light = 0;  // light instance id (LoadScene's lights[].id)
  std::optional<glm::vec3> color;
  std::optional<float> intensity;
  std::optional<glm::vec3> position;   // world space
  std::optional<glm::vec3> direction;  // world space
  std::optional<float> inner_cone_angle;
  std::optional<float> outer_cone_angle;
};

struct LookAt {
  glm::vec3 eye{0.0f};
  glm::vec3 target{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
};

struct CameraPose {
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // looks down -Z
};

struct CameraUpdate {
  std::optional<LookAt> look_at;
  std::optional<CameraPose> pose;
  std::optional<uint32_t> scene_camera;
  std::optional<float> yfov_degrees;
  std::optional<uint32_t> width;
  std::optional<uint32_t> height;
};

struct MaterialUpdate {
  uint32_t material = 0;
  std::optional<glm::vec4> base_color;
  std::optional<glm::vec3> emissive;
  std::optional<float> emissive_strength;
  std::optional<float> metallic;   // [0, 1] (glTF metallicFactor)
  std::optional<float> roughness;  // [0, 1] (glTF roughnessFactor)
};

struct EnvironmentUpdate {
  std::optional<float> rotation;
  std::optional<float> intensity;
};

// Playback of one of the scene's glTF animations (by index or by name,
// exactly one): play or pause, seek, speed, looping. The scene's animation
// clock advances playing animations with the time between frames.
struct AnimationUpdate {
  std::optional<uint32_t> animation;  // index into the scene's animations
  std::optional<std::string> name;    // or its name
  std::optional<bool> playing;        // true: play, false: pause
  std::optional<float> time;          // seek (seconds, on the animation's keys)
  std::optional<float> speed;         // playback rate; negative plays backwards
  std::optional<bool> loop;           // wrap at the end (default) or stop there
};

// Morph weights of one node that draws a mesh with morph targets; one per
// target (glTF node.weights). Joints are nodes: NodeTransformUpdate poses them.
struct MorphWeightsUpdate {
  uint32_t node = 0;
  std::vector<float> weights;
};

using Change = std::variant<NodeTransformUpdate, LightUpdate, CameraUpdate, MaterialUpdate,
                            EnvironmentUpdate, AnimationUpdate, MorphWeightsUpdate>;

struct Update {
  uint64_t seq = 0;
  Change change;
};

// What kind of thing changed, so solvers run only the stages a change needs.
enum ChangeBits : uint32_t {
  kChangeNone = 0,
  kChangeGeometry = 1u << 0,     // a node carrying a mesh moved
  kChangeLights = 1u << 1,       // punctual light moved/recoloured/dimmed
  kChangeEmission = 1u << 2,     // emissive material changed (area lights)
  kChangeMaterials = 1u << 3,    // base colour, metallic or roughness changed
  kChangeEnvironment = 1u << 4,  // environment rotation/intensity
  kChangeCamera = 1u << 5,       // view only (per session)
  kChangeDeformation = 1u << 6,  // a skinned or morphed mesh changed shape (joints, weights)
  kChangeAll = 0xffffffffu,
};
using ChangeMask = uint32_t;
// Where the surfaces are: a rigid move or a deformation. Solvers that keep
// geometry (a BVH, voxels, elements, cube maps) redo it for either.
inline constexpr ChangeMask kChangeShape = kChangeGeometry | kChangeDeformation;

}  // namespace gistream
