// The `gistream script` timeline file: parsed and validated into plain
// structs, with every error naming its JSON path
// ("tracks[1].keys[0].translation: expected 3 numbers"). No network here:
// names of nodes, lights and materials are resolved later (timeline.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <absl/strings/string_view.h>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "gistream/v1/gistream.pb.h"
#include "util/status.h"

namespace gistream::client {

// A keyed value: linear between keys (slerp for rotations), the first
// key's value before it, the last key's value after it.
template <typename T>
struct Curve {
  std::vector<std::pair<int, T>> keys;  // frames strictly increasing
  bool empty() const { return keys.empty(); }
  T At(int frame) const;
};

// A node, light or material named by its name or its numeric id.
struct ObjectRef {
  std::string name;  // empty when `id` is given
  std::optional<uint32_t> id;
  std::string path;  // JSON path, for errors: "tracks[1].node"
};

struct CameraOrbitTrack {
  glm::vec3 target{0.0f};
  float radius = 1.0f;
  float height = 0.0f;  // world y of the camera
  float start_deg = 0.0f;
  float end_deg = 0.0f;
  std::optional<float> yfov_degrees;
};

struct CameraPathTrack {
  Curve<glm::vec3> eye, target;
  Curve<float> yfov_degrees;
};

struct NodePathTrack {
  ObjectRef node;
  Curve<glm::vec3> translation;
  Curve<glm::quat> rotation;
  Curve<glm::vec3> scale;
};

struct NodeSpinTrack {
  ObjectRef node;
  glm::vec3 axis{0.0f, 1.0f, 0.0f};  // unit length
  float degrees_per_frame = 0.0f;
};

struct LightTrack {
  ObjectRef light;
  Curve<float> intensity;
  Curve<glm::vec3> color, position, direction;
  Curve<float> inner_cone_angle, outer_cone_angle;  // radians
};

struct MaterialTrack {
  ObjectRef material;
  Curve<glm::vec4> base_color;
  bool base_color_rgba = false;  // keys gave 4 numbers (else RGB is sent)
  Curve<glm::vec3> emissive;
  Curve<float> emissive_strength;
  Curve<float> metallic, roughness;  // [0, 1] (glTF metallic-roughness, GGX)
};

struct EnvironmentTrack {
  Curve<float> rotation;  // radians about +Y
  Curve<float> intensity;
};

struct Track {
  std::string path;  // "tracks[2]"
  std::variant<CameraOrbitTrack, CameraPathTrack, NodePathTrack, NodeSpinTrack, LightTrack,
               MaterialTrack, EnvironmentTrack>
      spec;
};

// A one-off Update (protobuf JSON) sent at `frame`; its seq is assigned
// when it is sent.
struct ScriptEvent {
  int frame = 0;
  v1::Update update;
  std::string path;  // "events[0]"
};

struct Script {
  std::string scene;  // a name, or a file (relative to the script's folder)
  std::string environment;
  float environment_intensity = 0.0f;
  std::string solver = "direct";
  std::map<std::string, std::string> params;
  uint32_t width = 320;
  uint32_t height = 240;
  v1::Encoding encoding;
  int frames = 0;
  std::vector<Track> tracks;
  std::vector<ScriptEvent> events;
};

// INVALID_ARGUMENT, prefixed with `label` (the file name).
absl::StatusOr<Script> ParseScript(absl::string_view json_text, absl::string_view label);
absl::StatusOr<Script> LoadScriptFile(const std::filesystem::path& path);

// Curve interpolation, per value type.
float Lerp(float a, float b, float t);
glm::vec3 Lerp(const glm::vec3& a, const glm::vec3& b, float t);
glm::vec4 Lerp(const glm::vec4& a, const glm::vec4& b, float t);
glm::quat Lerp(const glm::quat& a, const glm::quat& b, float t);  // slerp

template <typename T>
T Curve<T>::At(int frame) const {
  if (frame <= keys.front().first) return keys.front().second;
  if (frame >= keys.back().first) return keys.back().second;
  size_t next = 1;
  while (keys[next].first < frame) ++next;
  const auto& [f0, value0] = keys[next - 1];
  const auto& [f1, value1] = keys[next];
  return Lerp(value0, value1, static_cast<float>(frame - f0) / static_cast<float>(f1 - f0));
}

}  // namespace gistream::client
