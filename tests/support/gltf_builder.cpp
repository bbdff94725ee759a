#include "support/gltf_builder.h"

#include <cmath>
#include <cstring>

namespace gistream::testing {
namespace {

std::string Base64(const std::vector<uint8_t>& data) {
  static const char* kChars = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < data.size(); i += 3) {
    const uint32_t v = (uint32_t(data[i]) << 16) | (uint32_t(data[i + 1]) << 8) | data[i + 2];
    for (int k = 3; k >= 0; --k) out += kChars[(v >> (6 * k)) & 63];
  }
  if (i + 1 == data.size()) {
    const uint32_t v = uint32_t(data[i]) << 16;
    out += kChars[(v >> 18) & 63];
    out += kChars[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == data.size()) {
    const uint32_t v = (uint32_t(data[i]) << 16) | (uint32_t(data[i + 1]) << 8);
    out += kChars[(v >> 18) & 63];
    out += kChars[(v >> 12) & 63];
    out += kChars[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

GltfBuilder::Vec3 Cross(GltfBuilder::Vec3 a, GltfBuilder::Vec3 b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

GltfBuilder::Vec3 Normalize(GltfBuilder::Vec3 a) {
  const float l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  return {a[0] / l, a[1] / l, a[2] / l};
}

// Quaternion (x, y, z, w) of the rotation whose columns are right, up, back.
std::array<float, 4> QuatFromBasis(GltfBuilder::Vec3 r, GltfBuilder::Vec3 u, GltfBuilder::Vec3 b) {
  const float m00 = r[0], m11 = u[1], m22 = b[2];
  const float trace = m00 + m11 + m22;
  std::array<float, 4> q{};
  if (trace > 0) {
    const float s = std::sqrt(trace + 1.0f) * 2.0f;
    q = {(u[2] - b[1]) / s, (b[0] - r[2]) / s, (r[1] - u[0]) / s, 0.25f * s};
  } else if (m00 > m11 && m00 > m22) {
    const float s = std::sqrt(1.0f + m00 - m11 - m22) * 2.0f;
    q = {0.25f * s, (u[0] + r[1]) / s, (b[0] + r[2]) / s, (u[2] - b[1]) / s};
  } else if (m11 > m22) {
    const float s = std::sqrt(1.0f + m11 - m00 - m22) * 2.0f;
    q = {(u[0] + r[1]) / s, 0.25f * s, (b[1] + u[2]) / s, (b[0] - r[2]) / s};
  } else {
    const float s = std::sqrt(1.0f + m22 - m00 - m11) * 2.0f;
    q = {(b[0] + r[2]) / s, (b[1] + u[2]) / s, 0.25f * s, (r[1] - u[0]) / s};
  }
  return q;
}

}  // namespace

int GltfBuilder::AddMaterial(const std::string& name, Vec3 base_color, Vec3 emissive,
                             float emissive_strength) {
  nlohmann::json m = {{"name", name},
                      {"pbrMetallicRoughness",
                       {{"baseColorFactor", {base_color[0], base_color[1], base_color[2], 1.0}},
                        {"metallicFactor", 0.0},
                        {"roughnessFactor", 1.0}}},
                      {"emissiveFactor", {emissive[0], emissive[1], emissive[2]}}};
  if (emissive_strength != 1.0f) {
    m["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = emissive_strength;
  }
  materials_.push_back(m);
  return int(materials_.size()) - 1;
}

int GltfBuilder::AddAccessor(const std::vector<float>& data, int components, bool with_bounds) {
  while (buffer_.size() % 4) buffer_.push_back(0);
  const size_t offset = buffer_.size();
  buffer_.resize(offset + data.size() * 4);
  std::memcpy(buffer_.data() + offset, data.data(), data.size() * 4);
  views_.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", data.size() * 4}});
  nlohmann::json a = {{"bufferView", views_.size() - 1},
                      {"componentType", 5126},
                      {"count", data.size() / size_t(components)},
                      {"type", components == 3 ? "VEC3" : "VEC2"}};
  if (with_bounds) {
    std::vector<float> lo(size_t(components), 1e30f), hi(size_t(components), -1e30f);
    for (size_t i = 0; i < data.size(); ++i) {
      lo[i % size_t(components)] = std::min(lo[i % size_t(components)], data[i]);
      hi[i % size_t(components)] = std::max(hi[i % size_t(components)], data[i]);
    }
    a["min"] = lo;
    a["max"] = hi;
  }
  accessors_.push_back(a);
  return int(accessors_.size()) - 1;
}

int GltfBuilder::AddIndices(const std::vector<uint32_t>& data) {
  while (buffer_.size() % 4) buffer_.push_back(0);
  const size_t offset = buffer_.size();
  buffer_.resize(offset + data.size() * 4);
  std::memcpy(buffer_.data() + offset, data.data(), data.size() * 4);
  views_.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", data.size() * 4}});
  accessors_.push_back({{"bufferView", views_.size() - 1},
                        {"componentType", 5125},
                        {"count", data.size()},
                        {"type", "SCALAR"}});
  return int(accessors_.size()) - 1;
}

int GltfBuilder::AddNode(nlohmann::json node) {
  nodes_.push_back(std::move(node));
  return int(nodes_.size()) - 1;
}

int GltfBuilder::AddQuad(const std::string& name, Vec3 center, Vec3 u, Vec3 v, int material,
                         int n) {
  const Vec3 normal = Normalize(Cross(u, v));
  std::vector<float> positions, normals, uvs;
  std::vector<uint32_t> indices;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float s = 2.0f * float(i) / float(n) - 1.0f, t = 2.0f * float(j) / float(n) - 1.0f;
      for (int k = 0; k < 3; ++k)
        positions.push_back(center[size_t(k)] + s * u[size_t(k)] + t * v[size_t(k)]);
      normals.insert(normals.end(), normal.begin(), normal.end());
      uvs.insert(uvs.end(), {0.5f * (s + 1.0f), 0.5f * (t + 1.0f)});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      indices.insert(indices.end(), {a, b, d, a, d, c});  // counter-clockwise about normal
    }
  }
  const int pos = AddAccessor(positions, 3, true);
  const int nrm = AddAccessor(normals, 3, false);
  const int idx = AddIndices(indices);
  nlohmann::json attributes = {{"POSITION", pos}, {"NORMAL", nrm}};
  if (uvs_) attributes["TEXCOORD_0"] = AddAccessor(uvs, 2, false);
  meshes_.push_back(
      {{"name", name},
       {"primitives", {{{"attributes", attributes}, {"indices", idx}, {"material", material}}}}});
  return AddNode({{"name", name}, {"mesh", meshes_.size() - 1}});
}

int GltfBuilder::AddTexture(const std::string& png, const nlohmann::json& sampler) {
  images_.push_back(
      {{"uri", "data:image/png;base64," + Base64(std::vector<uint8_t>(png.begin(), png.end()))}});
  textures_.push_back({{"source", images_.size() - 1}});
  if (!sampler.is_null()) {
    samplers_.push_back(sampler);
    textures_.back()["sampler"] = samplers_.size() - 1;
  }
  return int(textures_.size()) - 1;
}

void GltfBuilder::SetTexture(int material, const std::string& slot, nlohmann::json info) {
  nlohmann::json& m = materials_[size_t(material)];
  if (slot == "baseColorTexture" || slot == "metallicRoughnessTexture") {
    m["pbrMetallicRoughness"][slot] = std::move(info);
  } else {
    m[slot] = std::move(info);
  }
}

int GltfBuilder::AddPointLight(const std::string& name, Vec3 position, Vec3 color,
                               float intensity) {
  lights_.push_back(
      {{"name", name}, {"type", "point"}, {"color", color}, {"intensity", intensity}});
  return AddNode({{"name", name},
                  {"translation", position},
                  {"extensions", {{"KHR_lights_punctual", {{"light", lights_.size() - 1}}}}}});
}

int GltfBuilder::AddSpotLightDown(const std::string& name, Vec3 position, Vec3 color,
                                  float intensity, float inner_cone, float outer_cone) {
  lights_.push_back({{"name", name},
                     {"type", "spot"},
                     {"color", color},
                     {"intensity", intensity},
                     {"spot", {{"innerConeAngle", inner_cone}, {"outerConeAngle", outer_cone}}}});
  // Spot lights shine along local -Z; -90 degrees about X turns -Z to -Y.
  const float h = 0.70710678f;
  return AddNode({{"name", name},
                  {"translation", position},
                  {"rotation", {-h, 0.0f, 0.0f, h}},
                  {"extensions", {{"KHR_lights_punctual", {{"light", lights_.size() - 1}}}}}});
}

int GltfBuilder::AddCamera(const std::string& name, Vec3 position, Vec3 forward, Vec3 up,
                           float yfov, float znear) {
  const Vec3 back = Normalize({-forward[0], -forward[1], -forward[2]});
  const Vec3 right = Normalize(Cross(up, back));
  const Vec3 true_up = Cross(back, right);
  cameras_.push_back({{"name", name},
                      {"type", "perspective"},
                      {"perspective", {{"yfov", yfov}, {"znear", znear}}}});
  return AddNode({{"name", name},
                  {"translation", position},
                  {"rotation", QuatFromBasis(right, true_up, back)},
                  {"camera", cameras_.size() - 1}});
}

std::string GltfBuilder::ToJson() const {
  nlohmann::json root;
  root["asset"] = {{"version", "2.0"}, {"generator", "gistream tests"}};
  std::vector<int> all(nodes_.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = int(i);
  root["scene"] = 0;
  root["scenes"] = {{{"nodes", all}}};
  root["nodes"] = nodes_;
  if (!meshes_.empty()) root["meshes"] = meshes_;
  if (!materials_.empty()) root["materials"] = materials_;
  root["accessors"] = accessors_;
  root["bufferViews"] = views_;
  root["buffers"] = {{{"byteLength", buffer_.size()},
                      {"uri", "data:application/octet-stream;base64," + Base64(buffer_)}}};
  if (!cameras_.empty()) root["cameras"] = cameras_;
  if (!images_.empty()) root["images"] = images_;
  if (!textures_.empty()) root["textures"] = textures_;
  if (!samplers_.empty()) root["samplers"] = samplers_;
  std::vector<std::string> used;
  if (!lights_.empty()) {
    root["extensions"]["KHR_lights_punctual"]["lights"] = lights_;
    used.push_back("KHR_lights_punctual");
  }
  used.push_back("KHR_materials_emissive_strength");
  root["extensionsUsed"] = used;
  return root.dump();
}

}  // namespace gistream::testing
