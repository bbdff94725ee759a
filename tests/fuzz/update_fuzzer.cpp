// Update validation (service/grpc/translate.* UpdateFromProto, then
// scene/validate_update.* and SceneState::CheckApply, as a Session applies
// them): any protobuf bytes are refused with a status or accepted, and an
// accepted update never takes the scene out of its magnitude limits or
// makes a world matrix, light or material non-finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <google/protobuf/stubs/logging.h>

#include "fuzz/fuzz_check.h"
#include "scene/gltf/gltf_import.h"
#include "scene/state/scene_state.h"
#include "scene/state/validate_update.h"
#include "service/translate.h"

using namespace gistream;

namespace {

// A floor, an emissive quad, a point and a spot light, a camera; nodes 4
// and 5 are a parent and a child.
constexpr char kScene[] = R"({
  "asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "point", "color": [1, 1, 1], "intensity": 5},
    {"type": "spot", "intensity": 3, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}]}},
  "scene": 0,
  "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
  "nodes": [
    {"mesh": 0},
    {"mesh": 0, "translation": [0, 1.5, 0], "scale": [0.2, 1, 0.2]},
    {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 1, 0]},
    {"camera": 0, "translation": [0, 1, 3]},
    {"children": [5], "translation": [1, 0, 0]},
    {"mesh": 0, "scale": [0.5, 0.5, 0.5], "extensions": {"KHR_lights_punctual": {"light": 1}}}],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
  "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1]},
                 "emissiveFactor": [1, 1, 1],
                 "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
     "min": [-1, 0, -1], "max": [1, 0, 1]},
    {"bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR"}],
  "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 24}],
  "buffers": [{"byteLength": 72, "uri": "data:application/octet-stream;base64,AACAvwAAAAAAAIC/AACAPwAAAAAAAIC/AACAPwAAAAAAAIA/AACAvwAAAAAAAIA/AAAAAAMAAAACAAAAAAAAAAIAAAABAAAA"}]
})";

const Scene& TheScene() {
  static const Scene* scene = [] {
    ImportOptions options;
    options.name = "fuzz";
    absl::StatusOr<Scene> imported = ImportGltf(
        std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(kScene), sizeof(kScene) - 1),
        options);
    FUZZ_CHECK(imported.ok());
    return new Scene(*std::move(imported));
  }();
  return *scene;
}

bool Finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

// Invalid UTF-8 in string fields is a parse failure; protobuf logs each one.
extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  google::protobuf::SetLogHandler(nullptr);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  v1::SessionRequest request;  // one or more updates, as a client sends them
  if (!request.ParseFromArray(data, int(size)) || !request.has_update()) return 0;
  absl::StatusOr<Update> update = service::UpdateFromProto(request.update(), "update");
  if (!update.ok()) return 0;
  const Scene& scene = TheScene();
  if (!ValidateUpdate(scene, *update, 4096, 4096).ok()) return 0;
  SceneState state(std::make_shared<const Scene>(scene));
  if (std::holds_alternative<CameraUpdate>(update->change)) return 0;
  if (!state.CheckApply(update->change).ok()) return 0;
  state.Apply(update->change);
  FUZZ_CHECK(state.CheckMagnitudes("").ok());
  for (const glm::mat4& m : state.world()) {
    for (int c = 0; c < 4; ++c) FUZZ_CHECK(Finite(glm::vec3(m[c])) && std::isfinite(m[c][3]));
  }
  for (const LightInstance& l : state.lights()) {
    FUZZ_CHECK(Finite(l.position) && Finite(l.direction) &&
               Finite(l.light.color * l.light.intensity));
  }
  for (const Material& m : state.materials()) FUZZ_CHECK(Finite(m.emission()));
  return 0;
}
