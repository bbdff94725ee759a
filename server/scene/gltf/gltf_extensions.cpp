// The glTF extensions a file uses that gistream renders without (issue 29:
// "Nothing tells the client an extension was ignored").
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "scene/gltf/gltf_stages.h"

namespace gistream::gltf {
namespace {

// What import reads. README ("glTF support") lists the decision for every
// ratified KHR extension.
const std::set<std::string, std::less<>> kRead = {
    "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_texture_transform"};

// Read per material (ClassifyDielectricSpecular): reported only for the
// materials whose values the BRDF cannot follow.
const std::set<std::string, std::less<>> kDielectricSpecular = {"KHR_materials_ior",
                                                                "KHR_materials_specular"};

void Collect(const tinygltf::ExtensionMap& extensions, std::set<std::string>* out) {
  for (const auto& [name, value] : extensions) {
    if (!kDielectricSpecular.contains(name)) out->insert(name);
  }
}

// A number member of an extension object, or `fallback` when absent or not
// a number (the preflight has refused wrong types already).
double Number(const tinygltf::Value& object, const char* key, double fallback) {
  if (!object.IsObject() || !object.Has(key)) return fallback;
  const tinygltf::Value& v = object.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

void CollectTexture(const tinygltf::TextureInfo& info, std::set<std::string>* out) {
  Collect(info.extensions, out);
}

}  // namespace

DielectricFresnel ClassifyDielectricSpecular(const tinygltf::Material& material) {
  DielectricFresnel out;
  const auto ior_ext = material.extensions.find("KHR_materials_ior");
  const auto spec_ext = material.extensions.find("KHR_materials_specular");
  const bool has_ior = ior_ext != material.extensions.end();
  const bool has_spec = spec_ext != material.extensions.end();
  if (!has_ior && !has_spec) return out;
  const tinygltf::Value none;
  const tinygltf::Value& spec = has_spec ? spec_ext->second : none;
  double ior = has_ior ? Number(ior_ext->second, "ior", 1.5) : 1.5;
  const bool ior_valid = ior >= 1.0 && std::isfinite(ior);
  if (!ior_valid) ior = 1.5;
  const double factor = std::clamp(Number(spec, "specularFactor", 1.0), 0.0, 1.0);
  double color[3] = {1.0, 1.0, 1.0};
  if (spec.IsObject() && spec.Has("specularColorFactor")) {
    const tinygltf::Value& c = spec.Get("specularColorFactor");
    for (int i = 0; i < 3 && c.IsArray() && c.ArrayLen() == 3; ++i) {
      if (c.Get(i).IsNumber()) color[i] = std::max(0.0, c.Get(i).GetNumberAsDouble());
    }
  }
  // KHR_materials_specular: dielectric F0 = min(F0(ior) specularColor, 1)
  // specularFactor, F90 = specularFactor; F0(ior) = ((ior - 1) / (ior + 1))^2
  // (KHR_materials_ior; 0.04 at the default 1.5).
  const double r = (ior - 1.0) / (ior + 1.0);
  for (int i = 0; i < 3; ++i) out.f0[i] = float(std::min(r * r * color[i], 1.0) * factor);
  out.f90 = float(factor);
  const bool textured =
      spec.IsObject() && (spec.Has("specularTexture") || spec.Has("specularColorTexture"));
  // A non-metal without a specular layer: f = baseColor / pi, the BRDF's
  // Lambertian case (its diffuse lobe's Fresnel weights are 1 when F = 0;
  // a specular texture scales the factor 0).
  if (factor == 0.0 && material.pbrMetallicRoughness.metallicFactor == 0.0) {
    out.kind = DielectricSpecular::kNone;
  } else {
    out.kind = textured || !ior_valid ? DielectricSpecular::kIgnored : DielectricSpecular::kRead;
  }
  return out;
}

std::vector<std::string> IgnoredExtensions(const tinygltf::Model& model) {
  std::set<std::string> used;
  for (const std::string& name : model.extensionsUsed) {
    if (!kDielectricSpecular.contains(name)) used.insert(name);
  }
  // A file that uses an extension without declaring it (invalid, common).
  Collect(model.extensions, &used);
  for (const tinygltf::Material& m : model.materials) {
    Collect(m.extensions, &used);
    if (ClassifyDielectricSpecular(m).kind == DielectricSpecular::kIgnored) {
      for (const std::string& name : kDielectricSpecular) {
        if (m.extensions.count(name) != 0) used.insert(name);
      }
    }
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
