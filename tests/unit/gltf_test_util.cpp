#include "gltf_test_util.h"

#include <cstring>

namespace gistream::testing {
namespace {

constexpr int kFloat = 5126;
constexpr int kUShort = 5123;

uint32_t Crc32(const uint8_t* data, size_t size, uint32_t crc = 0) {
  crc = ~crc;
  for (size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void PutU32BE(std::vector<uint8_t>* out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out->push_back(uint8_t(v >> shift));
}

void PutU32LE(std::vector<uint8_t>* out, uint32_t v) {
  for (int shift = 0; shift < 32; shift += 8) out->push_back(uint8_t(v >> shift));
}

void PngChunk(std::vector<uint8_t>* out, const char* type, const std::vector<uint8_t>& data) {
  PutU32BE(out, uint32_t(data.size()));
  std::vector<uint8_t> typed(type, type + 4);
  typed.insert(typed.end(), data.begin(), data.end());
  out->insert(out->end(), typed.begin(), typed.end());
  PutU32BE(out, Crc32(typed.data(), typed.size()));
}

}  // namespace

TestGltf::TestGltf() {
  doc = {{"asset", {{"version", "2.0"}}},
         {"scene", 0},
         {"scenes", nlohmann::json::array({{{"nodes", nlohmann::json::array()}}})}};
}

int TestGltf::AddView(const void* data, size_t bytes, size_t stride) {
  while (bin.size() % 4 != 0) bin.push_back(0);
  const size_t offset = bin.size();
  bin.resize(offset + bytes);
  std::memcpy(bin.data() + offset, data, bytes);
  nlohmann::json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
  if (stride != 0) view["byteStride"] = stride;
  doc["bufferViews"].push_back(view);
  return int(doc["bufferViews"].size()) - 1;
}

int TestGltf::AddAccessor(int view, int component_type, size_t count, const std::string& type,
                          size_t byte_offset) {
  nlohmann::json a = {
      {"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}};
  if (byte_offset != 0) a["byteOffset"] = byte_offset;
  doc["accessors"].push_back(a);
  return int(doc["accessors"].size()) - 1;
}

int TestGltf::AddVec3(const std::vector<float>& xyz) {
  const int view = AddView(xyz.data(), xyz.size() * 4);
  const int a = AddAccessor(view, kFloat, xyz.size() / 3, "VEC3");
  std::vector<float> lo(3, 1e30f), hi(3, -1e30f);
  for (size_t i = 0; i < xyz.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], xyz[i]);
    hi[i % 3] = std::max(hi[i % 3], xyz[i]);
  }
  doc["accessors"][size_t(a)]["min"] = lo;
  doc["accessors"][size_t(a)]["max"] = hi;
  return a;
}

int TestGltf::AddVec2(const std::vector<float>& uv) {
  return AddAccessor(AddView(uv.data(), uv.size() * 4), kFloat, uv.size() / 2, "VEC2");
}

int TestGltf::AddIndices16(const std::vector<uint16_t>& indices) {
  return AddAccessor(AddView(indices.data(), indices.size() * 2), kUShort, indices.size(),
                     "SCALAR");
}

int TestGltf::AddMesh(nlohmann::json primitive) {
  doc["meshes"].push_back({{"primitives", nlohmann::json::array({primitive})}});
  return int(doc["meshes"].size()) - 1;
}

int TestGltf::AddNode(nlohmann::json node) {
  if (node.is_null()) node = nlohmann::json::object();  // `{}` reads as null
  doc["nodes"].push_back(node);
  return int(doc["nodes"].size()) - 1;
}

int TestGltf::AddRoot(nlohmann::json node) {
  const int n = AddNode(std::move(node));
  doc["scenes"][0]["nodes"].push_back(n);
  return n;
}

int TestGltf::AddMaterial(nlohmann::json material) {
  doc["materials"].push_back(material);
  return int(doc["materials"].size()) - 1;
}

std::vector<uint8_t> TestGltf::ToGltf() const {
  nlohmann::json d = doc;
  if (!bin.empty()) {
    d["buffers"] =
        nlohmann::json::array({{{"byteLength", bin.size()},
                                {"uri", "data:application/octet-stream;base64," + Base64(bin)}}});
  }
  return Bytes(d.dump());
}

std::vector<uint8_t> TestGltf::ToGlb() const {
  nlohmann::json d = doc;
  if (!bin.empty()) d["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
  return PackGlb(d.dump(), bin);
}

int AddQuadMesh(TestGltf* gltf, bool with_normals, int material) {
  nlohmann::json attributes = {
      {"POSITION", gltf->AddVec3({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0})}};
  if (with_normals) attributes["NORMAL"] = gltf->AddVec3({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  nlohmann::json primitive = {{"attributes", attributes},
                              {"indices", gltf->AddIndices16({0, 1, 2, 0, 2, 3})}};
  if (material >= 0) primitive["material"] = material;
  return gltf->AddMesh(primitive);
}

std::string Base64(const std::vector<uint8_t>& bytes) {
  static const char* kTable = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = (uint32_t(bytes[i]) << 16) |
                       (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
                       (i + 2 < bytes.size() ? uint32_t(bytes[i + 2]) : 0);
    out += kTable[(n >> 18) & 63];
    out += kTable[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kTable[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kTable[n & 63] : '=';
  }
  return out;
}

std::vector<uint8_t> PackGlb(const std::string& json, const std::vector<uint8_t>& bin) {
  std::string text = json;
  while (text.size() % 4 != 0) text += ' ';
  std::vector<uint8_t> payload = bin;
  while (payload.size() % 4 != 0) payload.push_back(0);
  const size_t total = 12 + 8 + text.size() + (payload.empty() ? 0 : 8 + payload.size());
  std::vector<uint8_t> out;
  PutU32LE(&out, 0x46546c67);
  PutU32LE(&out, 2);
  PutU32LE(&out, uint32_t(total));
  PutU32LE(&out, uint32_t(text.size()));
  PutU32LE(&out, 0x4e4f534a);
  out.insert(out.end(), text.begin(), text.end());
  if (!payload.empty()) {
    PutU32LE(&out, uint32_t(payload.size()));
    PutU32LE(&out, 0x004e4942);
    out.insert(out.end(), payload.begin(), payload.end());
  }
  return out;
}

std::vector<uint8_t> Bytes(const std::string& s) {
  return std::vector<uint8_t>(s.begin(), s.end());
}

absl::StatusOr<Scene> Import(const std::vector<uint8_t>& bytes, const ImportOptions& options) {
  return ImportGltf(bytes, options);
}

std::vector<uint8_t> PngHeaderOnly(uint32_t width, uint32_t height) {
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<uint8_t> ihdr;
  PutU32BE(&ihdr, width);
  PutU32BE(&ihdr, height);
  ihdr.insert(ihdr.end(), {8, 6, 0, 0, 0});  // 8-bit RGBA, deflate, no interlace
  PngChunk(&png, "IHDR", ihdr);
  PngChunk(&png, "IDAT", {0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01});
  PngChunk(&png, "IEND", {});
  return png;
}

}  // namespace gistream::testing
