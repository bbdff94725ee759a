// Builds small self-contained glTF scenes in tests: quads, point lights,
// cameras; buffers are embedded as base64 data URIs.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gistream::testing {

class GltfBuilder {
 public:
  using Vec3 = std::array<float, 3>;

  // Returns the material index.
  int AddMaterial(const std::string& name, Vec3 base_color, Vec3 emissive = {0, 0, 0},
                  float emissive_strength = 1.0f);
  // Marks material `material` doubleSided (glTF: both faces are surfaces).
  void SetDoubleSided(int material) { materials_[size_t(material)]["doubleSided"] = true; }
  // Adds extension `name` with `value` to material `material` (e.g.
  // KHR_materials_specular).
  void SetMaterialExtension(int material, const std::string& name, nlohmann::json value) {
    materials_[size_t(material)]["extensions"][name] = std::move(value);
  }
  // Makes material `material` glossy (glTF metallicFactor, roughnessFactor).
  void SetMetallicRoughness(int material, float metallic, float roughness) {
    materials_[size_t(material)]["pbrMetallicRoughness"]["metallicFactor"] = metallic;
    materials_[size_t(material)]["pbrMetallicRoughness"]["roughnessFactor"] = roughness;
  }
  // A rectangle centred at `center` spanned by half-vectors u and v, facing
  // along normalize(cross(u, v)), tessellated n x n. Returns the node index.
  int AddQuad(const std::string& name, Vec3 center, Vec3 u, Vec3 v, int material, int n = 1);
  // Quads added after this carry TEXCOORD_0: (0, 0) at center - u - v, (1,
  // 1) at center + u + v.
  void EnableUvs() { uvs_ = true; }
  // An image (PNG bytes, as a data: URI) and a texture of it, with
  // `sampler` (a glTF sampler object) when given; returns the texture index.
  int AddTexture(const std::string& png, const nlohmann::json& sampler = nullptr);
  // Sets material `material`'s `slot` ("emissiveTexture", or
  // "baseColorTexture" under pbrMetallicRoughness) to `info` (index, texCoord,
  // extensions).
  void SetTexture(int material, const std::string& slot, nlohmann::json info);
  int AddPointLight(const std::string& name, Vec3 position, Vec3 color, float intensity);
  // A spot light shining straight down (-Y); cone angles in radians.
  int AddSpotLightDown(const std::string& name, Vec3 position, Vec3 color, float intensity,
                       float inner_cone, float outer_cone);
  // Camera at `position` looking along `forward` (unit) with `up`.
  int AddCamera(const std::string& name, Vec3 position, Vec3 forward, Vec3 up, float yfov,
                float znear = 0.01f);

  std::string ToJson() const;

 private:
  int AddNode(nlohmann::json node);
  int AddAccessor(const std::vector<float>& data, int components, bool with_bounds);
  int AddIndices(const std::vector<uint32_t>& data);

  std::vector<uint8_t> buffer_;
  nlohmann::json nodes_ = nlohmann::json::array();
  nlohmann::json meshes_ = nlohmann::json::array();
  nlohmann::json materials_ = nlohmann::json::array();
  nlohmann::json accessors_ = nlohmann::json::array();
  nlohmann::json views_ = nlohmann::json::array();
  nlohmann::json lights_ = nlohmann::json::array();
  nlohmann::json cameras_ = nlohmann::json::array();
  nlohmann::json images_ = nlohmann::json::array();
  nlohmann::json textures_ = nlohmann::json::array();
  nlohmann::json samplers_ = nlohmann::json::array();
  bool uvs_ = false;
};

}  // namespace gistream::testing
