// The glTF extensions a file uses that gistream renders without (issue 29:
// "Nothing tells the client an extension was ignored").
#include <set>
#include <string>
#include <vector>

#include "scene/gltf_stages.h"

namespace gistream::gltf {
namespace {

// What import reads. KHR_texture_transform is parsed and type-checked by the
// preflight but not applied, so it is reported; README ("glTF support")
// lists the decision for every ratified KHR extension.
const std::set<std::string, std::less<>> kRead = {"KHR_lights_punctual",
                                                  "KHR_materials_emissive_strength"};

void Collect(const tinygltf::ExtensionMap& extensions, std::set<std::string>* out) {
  for (const auto& [name, value] : extensions) out->insert(name);
}

void CollectTexture(const tinygltf::TextureInfo& info, std::set<std::string>* out) {
  Collect(info.extensions, out);
}

}  // namespace

std::vector<std::string> IgnoredExtensions(const tinygltf::Model& model) {
  std::set<std::string> used(model.extensionsUsed.begin(), model.extensionsUsed.end());
  // A file that uses an extension without declaring it (invalid, common).
  Collect(model.extensions, &used);
  for (const tinygltf::Material& m : model.materials) {
    Collect(m.extensions, &used);
    CollectTexture(m.pbrMetallicRoughness.baseColorTexture, &used);
    CollectTexture(m.pbrMetallicRoughness.metallicRoughnessTexture, &used);
    CollectTexture(m.emissiveTexture, &used);
    Collect(m.normalTexture.extensions, &used);
    Collect(m.occlusionTexture.extensions, &used);
  }
  for (const tinygltf::Node& n : model.nodes) Collect(n.extensions, &used);
  for (const tinygltf::Mesh& mesh : model.meshes) {
    Collect(mesh.extensions, &used);
    for (const tinygltf::Primitive& p : mesh.primitives) Collect(p.extensions, &used);
  }
  for (const tinygltf::Texture& t : model.textures) Collect(t.extensions, &used);
  std::vector<std::string> ignored;
  for (const std::string& name : used) {
    if (!kRead.contains(name)) ignored.push_back(name);
  }
  return ignored;
}

}  // namespace gistream::gltf
