#include "script.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>
#include <google/protobuf/util/json_util.h>
#include <nlohmann/json.hpp>

#include "file_io.h"
#include "image_format.h"

namespace gistream::client {
namespace {

using nlohmann::json;
using Keys = std::initializer_list<absl::string_view>;

constexpr int kMaxFrames = 1'000'000;
constexpr int64_t kMaxImageSide = 16384;
constexpr absl::string_view kTrackTypes =
    "camera_orbit, camera_path, node_path, node_spin, light, material, environment";

absl::Status Error(absl::string_view path, absl::string_view message) {
  return absl::InvalidArgumentError(absl::StrCat(path, ": ", message));
}

std::string Child(absl::string_view path, absl::string_view key) {
  return path.empty() ? std::string(key) : absl::StrCat(path, ".", key);
}

std::string Index(absl::string_view path, size_t i) { return absl::StrCat(path, "[", i, "]"); }

// Unknown keys are errors, so that a typo ("radus") is not silently
// ignored; "comment" is allowed everywhere.
absl::Status CheckKeys(const json& object, absl::string_view path, Keys allowed) {
  for (const auto& [key, value] : object.items()) {
    if (key == "comment" || std::find(allowed.begin(), allowed.end(), key) != allowed.end()) {
      continue;
    }
    return Error(Child(path, key),
                 absl::StrCat("unknown key (expected ", absl::StrJoin(allowed, ", "), ")"));
  }
  return absl::OkStatus();
}

absl::Status ExpectObject(const json& value, absl::string_view path) {
  if (!value.is_object())
    return Error(path, absl::StrCat("expected an object, got ", value.type_name()));
  return absl::OkStatus();
}

absl::StatusOr<const json*> Require(const json& object, absl::string_view key,
                                    absl::string_view path) {
  auto it = object.find(key);
  if (it == object.end()) return Error(Child(path, key), "required");
  return &*it;
}

absl::StatusOr<float> GetFloat(const json& value, absl::string_view path) {
  if (!value.is_number())
    return Error(path, absl::StrCat("expected a number, got ", value.type_name()));
  const double number = value.get<double>();
  if (!std::isfinite(number) || std::fabs(number) > std::numeric_limits<float>::max()) {
    return Error(path, absl::StrCat(number, " is not a finite 32-bit float"));
  }
  return static_cast<float>(number);
}

absl::StatusOr<float> GetNonNegative(const json& value, absl::string_view path) {
  GS_ASSIGN_OR_RETURN(float number, GetFloat(value, path));
  if (number < 0.0f) return Error(path, absl::StrCat(number, " is negative"));
  return number;
}

// glTF metallicFactor / roughnessFactor: [0, 1].
absl::StatusOr<float> GetUnitInterval(const json& value, absl::string_view path) {
  GS_ASSIGN_OR_RETURN(float number, GetFloat(value, path));
  if (!(number >= 0.0f && number <= 1.0f)) {
    return Error(path, absl::StrCat(number, " is outside [0, 1]"));
  }
  return number;
}

absl::StatusOr<int64_t> GetInt(const json& value, absl::string_view path, int64_t min,
                               int64_t max) {
  if (!value.is_number_integer()) {
    return Error(path, absl::StrCat("expected a whole number, got ",
                                    value.is_number() ? value.dump() : value.type_name()));
  }
  const int64_t number = value.is_number_unsigned()
                             ? static_cast<int64_t>(std::min<uint64_t>(
                                   value.get<uint64_t>(), std::numeric_limits<int64_t>::max()))
                             : value.get<int64_t>();
  if (number < min || number > max) {
    return Error(path, absl::StrCat(number, " is out of range [", min, ", ", max, "]"));
  }
  return number;
}

absl::StatusOr<std::string> GetString(const json& value, absl::string_view path) {
  if (!value.is_string())
    return Error(path, absl::StrCat("expected a string, got ", value.type_name()));
  std::string text = value.get<std::string>();
  if (text.empty()) return Error(path, "empty string");
  return text;
}

// An array of `min_count`..`max_count` finite numbers.
absl::StatusOr<std::vector<float>> GetFloats(const json& value, absl::string_view path,
                                             size_t min_count, size_t max_count) {
  const std::string expected =
      min_count == max_count ? absl::StrCat("expected ", min_count, " numbers")
                             : absl::StrCat("expected ", min_count, " or ", max_count, " numbers");
  if (!value.is_array() || value.size() < min_count || value.size() > max_count) {
    return Error(path, expected);
  }
  std::vector<float> numbers;
  for (size_t i = 0; i < value.size(); ++i) {
    if (!value[i].is_number()) return Error(path, expected);
    GS_ASSIGN_OR_RETURN(numbers.emplace_back(), GetFloat(value[i], Index(path, i)));
  }
  return numbers;
}

absl::StatusOr<glm::vec3> GetVec3(const json& value, absl::string_view path) {
  GS_ASSIGN_OR_RETURN(std::vector<float> v, GetFloats(value, path, 3, 3));
  return glm::vec3(v[0], v[1], v[2]);
}

absl::StatusOr<glm::vec3> GetColor(const json& value, absl::string_view path) {
  GS_ASSIGN_OR_RETURN(glm::vec3 color, GetVec3(value, path));
  if (color.r < 0.0f || color.g < 0.0f || color.b < 0.0f) return Error(path, "negative component");
  return color;
}

absl::StatusOr<glm::vec3> GetDirection(const json& value, absl::string_view path) {
  GS_ASSIGN_OR_RETURN(glm::vec3 direction, GetVec3(value, path));
  if (glm::length(direction) < 1e-12f) return Error(path, "zero-length direction");
  return glm::normalize(direction);
}

// glTF order: [x, y, z, w]; normalized here.
absl::StatusOr<glm::quat> GetQuat(const json& value, absl::string_view path) {
  GS_ASSIGN_OR_RETURN(std::vector<float> v, GetFloats(value, path, 4, 4));
  const glm::quat q(v[3], v[0], v[1], v[2]);
  if (glm::length(q) < 1e-12f) return Error(path, "zero-length quaternion (expected [x, y, z, w])");
  return glm::normalize(q);
}

absl::StatusOr<ObjectRef> GetRef(const json& track, absl::string_view key, absl::string_view path) {
  GS_ASSIGN_OR_RETURN(const json* value, Require(track, key, path));
  ObjectRef ref;
  ref.path = Child(path, key);
  if (value->is_string()) {
    GS_ASSIGN_OR_RETURN(ref.name, GetString(*value, ref.path));
  } else if (value->is_number_integer()) {
    GS_ASSIGN_OR_RETURN(int64_t id,
                        GetInt(*value, ref.path, 0, std::numeric_limits<uint32_t>::max()));
    ref.id = static_cast<uint32_t>(id);
  } else {
    return Error(ref.path, "expected a name or a numeric id");
  }
  return ref;
}

// Walks "keys": each an object with "frame" (strictly increasing) and at
// least one of `fields`, handed to `on_field(field, value, path, frame)`.
template <typename OnField>
absl::Status ParseKeys(const json& track, absl::string_view path, Keys fields, OnField&& on_field) {
  const std::string keys_path = Child(path, "keys");
  GS_ASSIGN_OR_RETURN(const json* keys, Require(track, "keys", path));
  if (!keys->is_array() || keys->empty())
    return Error(keys_path, "expected a non-empty array of keys");
  std::vector<absl::string_view> allowed(fields);
  allowed.push_back("frame");
  int previous = -1;
  for (size_t i = 0; i < keys->size(); ++i) {
    const json& key = (*keys)[i];
    const std::string key_path = Index(keys_path, i);
    GS_RETURN_IF_ERROR(ExpectObject(key, key_path));
    for (const auto& [name, value] : key.items()) {
      if (name != "comment" && std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
        return Error(Child(key_path, name),
                     absl::StrCat("unknown key (expected ", absl::StrJoin(allowed, ", "), ")"));
      }
    }
    GS_ASSIGN_OR_RETURN(const json* frame_value, Require(key, "frame", key_path));
    GS_ASSIGN_OR_RETURN(int64_t frame,
                        GetInt(*frame_value, Child(key_path, "frame"), 0, kMaxFrames));
    if (frame <= previous) {
      return Error(Child(key_path, "frame"),
                   absl::StrCat(frame, " is not after the previous key's frame ", previous));
    }
    previous = static_cast<int>(frame);
    int values = 0;
    for (absl::string_view field : fields) {
      auto it = key.find(field);
      if (it == key.end()) continue;
      GS_RETURN_IF_ERROR(on_field(field, *it, Child(key_path, field), previous));
      ++values;
    }
    if (values == 0) {
      return Error(key_path, absl::StrCat("no value (expected ", absl::StrJoin(fields, ", "), ")"));
    }
  }
  return absl::OkStatus();
}

// Appends a parsed value to `curve`.
template <typename T>
absl::Status AddKey(Curve<T>& curve, int frame, absl::StatusOr<T> value) {
  if (!value.ok()) return value.status();
  curve.keys.emplace_back(frame, *std::move(value));
  return absl::OkStatus();
}

absl::StatusOr<CameraOrbitTrack> ParseCameraOrbit(const json& t, absl::string_view path) {
  GS_RETURN_IF_ERROR(CheckKeys(
      t, path, {"type", "target", "radius", "height", "start_deg", "end_deg", "yfov_degrees"}));
  CameraOrbitTrack orbit;
  GS_ASSIGN_OR_RETURN(const json* target, Require(t, "target", path));
  GS_ASSIGN_OR_RETURN(orbit.target, GetVec3(*target, Child(path, "target")));
  GS_ASSIGN_OR_RETURN(const json* radius, Require(t, "radius", path));
  GS_ASSIGN_OR_RETURN(orbit.radius, GetFloat(*radius, Child(path, "radius")));
  if (orbit.radius <= 0.0f) return Error(Child(path, "radius"), "must be positive");
  GS_ASSIGN_OR_RETURN(const json* height, Require(t, "height", path));
  GS_ASSIGN_OR_RETURN(orbit.height, GetFloat(*height, Child(path, "height")));
  GS_ASSIGN_OR_RETURN(const json* start, Require(t, "start_deg", path));
  GS_ASSIGN_OR_RETURN(orbit.start_deg, GetFloat(*start, Child(path, "start_deg")));
  GS_ASSIGN_OR_RETURN(const json* end, Require(t, "end_deg", path));
  GS_ASSIGN_OR_RETURN(orbit.end_deg, GetFloat(*end, Child(path, "end_deg")));
  if (auto it = t.find("yfov_degrees"); it != t.end()) {
    GS_ASSIGN_OR_RETURN(float yfov, GetFloat(*it, Child(path, "yfov_degrees")));
    if (yfov <= 0.0f || yfov >= 180.0f) {
      return Error(Child(path, "yfov_degrees"), absl::StrCat(yfov, " is out of range (0, 180)"));
    }
    orbit.yfov_degrees = yfov;
  }
  return orbit;
}

absl::StatusOr<CameraPathTrack> ParseCameraPath(const json& t, absl::string_view path) {
  GS_RETURN_IF_ERROR(CheckKeys(t, path, {"type", "keys"}));
  CameraPathTrack camera;
  GS_RETURN_IF_ERROR(ParseKeys(
      t, path, {"eye", "target", "yfov_degrees"},
      [&](absl::string_view field, const json& v, const std::string& p, int frame) -> absl::Status {
        if (field == "eye") return AddKey(camera.eye, frame, GetVec3(v, p));
        if (field == "target") return AddKey(camera.target, frame, GetVec3(v, p));
        GS_ASSIGN_OR_RETURN(float yfov, GetFloat(v, p));
        if (yfov <= 0.0f || yfov >= 180.0f)
          return Error(p, absl::StrCat(yfov, " is out of range (0, 180)"));
        return AddKey(camera.yfov_degrees, frame, absl::StatusOr<float>(yfov));
      }));
  if (camera.eye.empty() || camera.target.empty()) {
    return Error(Child(path, "keys"), "needs an eye and a target (in at least one key each)");
  }
  return camera;
}

absl::StatusOr<NodePathTrack> ParseNodePath(const json& t, absl::string_view path) {
  GS_RETURN_IF_ERROR(CheckKeys(t, path, {"type", "node", "keys"}));
  NodePathTrack node;
  GS_ASSIGN_OR_RETURN(node.node, GetRef(t, "node", path));
  GS_RETURN_IF_ERROR(ParseKeys(
      t, path, {"translation", "rotation", "scale"},
      [&](absl::string_view field, const json& v, const std::string& p, int frame) -> absl::Status {
        if (field == "translation") return AddKey(node.translation, frame, GetVec3(v, p));
        if (field == "rotation") return AddKey(node.rotation, frame, GetQuat(v, p));
        return AddKey(node.scale, frame, GetVec3(v, p));
      }));
  return node;
}

absl::StatusOr<NodeSpinTrack> ParseNodeSpin(const json& t, absl::string_view path) {
  GS_RETURN_IF_ERROR(CheckKeys(t, path, {"type", "node", "axis", "degrees_per_frame"}));
  NodeSpinTrack spin;
  GS_ASSIGN_OR_RETURN(spin.node, GetRef(t, "node", path));
  if (auto it = t.find("axis"); it != t.end()) {
    GS_ASSIGN_OR_RETURN(spin.axis, GetDirection(*it, Child(path, "axis")));
  }
  GS_ASSIGN_OR_RETURN(const json* speed, Require(t, "degrees_per_frame", path));
  GS_ASSIGN_OR_RETURN(spin.degrees_per_frame, GetFloat(*speed, Child(path, "degrees_per_frame")));
  return spin;
}

absl::StatusOr<LightTrack> ParseLight(const json& t, absl::string_view path) {
  GS_RETURN_IF_ERROR(CheckKeys(t, path, {"type", "light", "keys"}));
  LightTrack light;
  GS_ASSIGN_OR_RETURN(light.light, GetRef(t, "light", path));
  GS_RETURN_IF_ERROR(ParseKeys(
      t, path,
      {"intensity", "color", "position", "direction", "inner_cone_angle", "outer_cone_angle"},
      [&](absl::string_view field, const json& v, const std::string& p, int frame) -> absl::Status {
        if (field == "intensity") return AddKey(light.intensity, frame, GetNonNegative(v, p));
        if (field == "color") return AddKey(light.color, frame, GetColor(v, p));
        if (field == "position") return AddKey(light.position, frame, GetVec3(v, p));
        if (field == "direction") return AddKey(light.direction, frame, GetDirection(v, p));
        if (field == "inner_cone_angle")
          return AddKey(light.inner_cone_angle, frame, GetNonNegative(v, p));
        return AddKey(light.outer_cone_angle, frame, GetNonNegative(v, p));
      }));
  return light;
}

absl::StatusOr<MaterialTrack> ParseMaterial(const json& t, absl::string_view path) {
  GS_RETURN_IF_ERROR(CheckKeys(t, path, {"type", "material", "keys"}));
  MaterialTrack material;
  GS_ASSIGN_OR_RETURN(material.material, GetRef(t, "material", path));
  GS_RETURN_IF_ERROR(ParseKeys(
      t, path, {"base_color", "emissive", "emissive_strength", "metallic", "roughness"},
      [&](absl::string_view field, const json& v, const std::string& p, int frame) -> absl::Status {
        if (field == "emissive") return AddKey(material.emissive, frame, GetColor(v, p));
        if (field == "metallic") return AddKey(material.metallic, frame, GetUnitInterval(v, p));
        if (field == "roughness") return AddKey(material.roughness, frame, GetUnitInterval(v, p));
        if (field == "emissive_strength") {
          return AddKey(material.emissive_strength, frame, GetNonNegative(v, p));
        }
        GS_ASSIGN_OR_RETURN(std::vector<float> c, GetFloats(v, p, 3, 4));
        const bool rgba = c.size() == 4;
        if (!material.base_color.empty() && rgba != material.base_color_rgba) {
          return Error(p, absl::StrCat(c.size(), " numbers, but earlier keys have ",
                                       material.base_color_rgba ? 4 : 3));
        }
        if (std::any_of(c.begin(), c.end(), [](float x) { return x < 0.0f; })) {
          return Error(p, "negative component");
        }
        material.base_color_rgba = rgba;
        return AddKey(material.base_color, frame,
                      absl::StatusOr<glm::vec4>(glm::vec4(c[0], c[1], c[2], rgba ? c[3] : 1.0f)));
      }));
  return material;
}

absl::StatusOr<EnvironmentTrack> ParseEnvironment(const json& t, absl::string_view path) {
  GS_RETURN_IF_ERROR(CheckKeys(t, path, {"type", "keys"}));
  EnvironmentTrack environment;
  GS_RETURN_IF_ERROR(ParseKeys(
      t, path, {"rotation", "intensity"},
      [&](absl::string_view field, const json& v, const std::string& p, int frame) -> absl::Status {
        if (field == "rotation") return AddKey(environment.rotation, frame, GetFloat(v, p));
        return AddKey(environment.intensity, frame, GetNonNegative(v, p));
      }));
  return environment;
}

absl::StatusOr<Track> ParseTrack(const json& t, const std::string& path) {
  GS_RETURN_IF_ERROR(ExpectObject(t, path));
  GS_ASSIGN_OR_RETURN(const json* type_value, Require(t, "type", path));
  GS_ASSIGN_OR_RETURN(std::string type, GetString(*type_value, Child(path, "type")));
  Track track{.path = path, .spec = {}};
  if (type == "camera_orbit") {
    GS_ASSIGN_OR_RETURN(track.spec, ParseCameraOrbit(t, path));
  } else if (type == "camera_path") {
    GS_ASSIGN_OR_RETURN(track.spec, ParseCameraPath(t, path));
  } else if (type == "node_path") {
    GS_ASSIGN_OR_RETURN(track.spec, ParseNodePath(t, path));
  } else if (type == "node_spin") {
    GS_ASSIGN_OR_RETURN(track.spec, ParseNodeSpin(t, path));
  } else if (type == "light") {
    GS_ASSIGN_OR_RETURN(track.spec, ParseLight(t, path));
  } else if (type == "material") {
    GS_ASSIGN_OR_RETURN(track.spec, ParseMaterial(t, path));
  } else if (type == "environment") {
    GS_ASSIGN_OR_RETURN(track.spec, ParseEnvironment(t, path));
  } else {
    return Error(Child(path, "type"),
                 absl::StrCat("unknown track type \"", type, "\" (expected ", kTrackTypes, ")"));
  }
  return track;
}

absl::StatusOr<ScriptEvent> ParseEvent(const json& e, const std::string& path, int frames) {
  GS_RETURN_IF_ERROR(ExpectObject(e, path));
  GS_RETURN_IF_ERROR(CheckKeys(e, path, {"frame", "update"}));
  ScriptEvent event;
  event.path = path;
  GS_ASSIGN_OR_RETURN(const json* frame, Require(e, "frame", path));
  GS_ASSIGN_OR_RETURN(int64_t frame_number, GetInt(*frame, Child(path, "frame"), 0, frames - 1));
  event.frame = static_cast<int>(frame_number);
  GS_ASSIGN_OR_RETURN(const json* update, Require(e, "update", path));
  const std::string update_path = Child(path, "update");
  GS_RETURN_IF_ERROR(ExpectObject(*update, update_path));
  const auto status = google::protobuf::util::JsonStringToMessage(update->dump(), &event.update);
  if (!status.ok()) {
    const auto message = status.message();
    return Error(update_path, absl::StrCat("not a gistream.v1.Update: ",
                                           absl::string_view(message.data(), message.size())));
  }
  if (event.update.change_case() == v1::Update::CHANGE_NOT_SET) {
    return Error(
        update_path,
        "no change (expected one of node_transform, light, camera, material, environment)");
  }
  event.update.set_seq(0);  // assigned when sent
  return event;
}

bool IsCameraTrack(const Track& track) {
  return std::holds_alternative<CameraOrbitTrack>(track.spec) ||
         std::holds_alternative<CameraPathTrack>(track.spec);
}

absl::Status ParseTopLevel(const json& doc, Script& script) {
  GS_RETURN_IF_ERROR(ExpectObject(doc, "script"));
  GS_RETURN_IF_ERROR(
      CheckKeys(doc, "",
                {"scene", "environment", "environment_intensity", "solver", "params", "size",
                 "format", "quality", "exposure", "frames", "tracks", "events", "description"}));
  GS_ASSIGN_OR_RETURN(const json* scene, Require(doc, "scene", ""));
  GS_ASSIGN_OR_RETURN(script.scene, GetString(*scene, "scene"));
  if (auto it = doc.find("environment"); it != doc.end()) {
    GS_ASSIGN_OR_RETURN(script.environment, GetString(*it, "environment"));
  }
  if (auto it = doc.find("environment_intensity"); it != doc.end()) {
    GS_ASSIGN_OR_RETURN(script.environment_intensity, GetNonNegative(*it, "environment_intensity"));
  }
  if (auto it = doc.find("solver"); it != doc.end()) {
    GS_ASSIGN_OR_RETURN(script.solver, GetString(*it, "solver"));
  }
  if (auto it = doc.find("params"); it != doc.end()) {
    GS_RETURN_IF_ERROR(ExpectObject(*it, "params"));
    for (const auto& [key, value] : it->items()) {
      if (value.is_string()) {
        script.params[key] = value.get<std::string>();
      } else if (value.is_boolean() || value.is_number()) {
        script.params[key] = value.dump();  // 32, 0.5, true: as written
      } else {
        return Error(Child("params", key), "expected a string, number or boolean");
      }
    }
  }
  if (auto it = doc.find("size"); it != doc.end()) {
    if (!it->is_array() || it->size() != 2) return Error("size", "expected [width, height]");
    GS_ASSIGN_OR_RETURN(int64_t width, GetInt((*it)[0], "size[0]", 1, kMaxImageSide));
    GS_ASSIGN_OR_RETURN(int64_t height, GetInt((*it)[1], "size[1]", 1, kMaxImageSide));
    script.width = static_cast<uint32_t>(width);
    script.height = static_cast<uint32_t>(height);
  }
  script.encoding.set_format(v1::IMAGE_FORMAT_JPEG);
  if (auto it = doc.find("format"); it != doc.end()) {
    GS_ASSIGN_OR_RETURN(std::string name, GetString(*it, "format"));
    auto format = ParseImageFormat(name);
    if (!format.ok()) return Error("format", format.status().message());
    script.encoding.set_format(*format);
  }
  if (auto it = doc.find("quality"); it != doc.end()) {
    GS_ASSIGN_OR_RETURN(int64_t quality, GetInt(*it, "quality", 1, 100));
    script.encoding.set_quality(static_cast<uint32_t>(quality));
  }
  if (auto it = doc.find("exposure"); it != doc.end()) {
    GS_ASSIGN_OR_RETURN(float exposure, GetFloat(*it, "exposure"));
    script.encoding.set_exposure(exposure);
  }
  GS_ASSIGN_OR_RETURN(const json* frames, Require(doc, "frames", ""));
  GS_ASSIGN_OR_RETURN(int64_t frame_count, GetInt(*frames, "frames", 1, kMaxFrames));
  script.frames = static_cast<int>(frame_count);

  if (auto it = doc.find("tracks"); it != doc.end()) {
    if (!it->is_array()) return Error("tracks", "expected an array of tracks");
    std::optional<std::string> camera_track;
    for (size_t i = 0; i < it->size(); ++i) {
      GS_ASSIGN_OR_RETURN(Track track, ParseTrack((*it)[i], Index("tracks", i)));
      if (IsCameraTrack(track)) {
        if (camera_track) {
          return Error(track.path, absl::StrCat("a second camera track (", *camera_track,
                                                " is one); keep one camera_orbit or camera_path"));
        }
        camera_track = track.path;
      }
      script.tracks.push_back(std::move(track));
    }
  }
  if (auto it = doc.find("events"); it != doc.end()) {
    if (!it->is_array()) return Error("events", "expected an array of events");
    for (size_t i = 0; i < it->size(); ++i) {
      GS_ASSIGN_OR_RETURN(ScriptEvent event,
                          ParseEvent((*it)[i], Index("events", i), script.frames));
      script.events.push_back(std::move(event));
    }
  }
  return absl::OkStatus();
}

}  // namespace

float Lerp(float a, float b, float t) { return a + (b - a) * t; }
glm::vec3 Lerp(const glm::vec3& a, const glm::vec3& b, float t) { return glm::mix(a, b, t); }
glm::vec4 Lerp(const glm::vec4& a, const glm::vec4& b, float t) { return glm::mix(a, b, t); }
glm::quat Lerp(const glm::quat& a, const glm::quat& b, float t) { return glm::slerp(a, b, t); }

absl::StatusOr<Script> ParseScript(absl::string_view json_text, absl::string_view label) {
  json doc;
  try {
    doc = json::parse(json_text);
  } catch (const json::exception& e) {
    // parse_error, and out_of_range for a number past a double ("8e888",
    // found by tests/fuzz/script_fuzzer: it ended the client).
    return absl::InvalidArgumentError(absl::StrCat(label, ": not valid JSON: ", e.what()));
  }
  Script script;
  if (absl::Status status = ParseTopLevel(doc, script); !status.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(label, ": ", status.message()));
  }
  return script;
}

absl::StatusOr<Script> LoadScriptFile(const std::filesystem::path& path) {
  GS_ASSIGN_OR_RETURN(std::string text, ReadFile(path));
  return ParseScript(text, path.string());
}

}  // namespace gistream::client
