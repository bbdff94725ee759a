// Helpers for import tests: a small glTF document builder (buffers embedded
// as a base64 data: URI or packed into a .glb) and status matchers.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/gltf/gltf_import.h"

namespace gistream::testing {

class TestGltf {
 public:
  TestGltf();

  nlohmann::json doc;  // edit freely; "buffers" is written by ToGltf/ToGlb
  std::vector<uint8_t> bin;

  // Appends bytes (4-byte aligned) and a bufferView over them.
  int AddView(const void* data, size_t bytes, size_t stride = 0);
  int AddAccessor(int view, int component_type, size_t count, const std::string& type,
                  size_t byte_offset = 0);
  int AddVec3(const std::vector<float>& xyz);  // FLOAT VEC3, with min/max
  int AddVec2(const std::vector<float>& uv);
  int AddIndices16(const std::vector<uint16_t>& indices);
  // A mesh with one primitive; returns the mesh index.
  int AddMesh(nlohmann::json primitive);
  int AddNode(nlohmann::json node);
  int AddRoot(nlohmann::json node);  // a node listed in scene 0
  int AddMaterial(nlohmann::json material);

  std::vector<uint8_t> ToGltf() const;  // JSON, buffer as data: URI
  std::vector<uint8_t> ToGlb() const;
};

// The unit quad [-1, 1]^2 on z = 0 facing +Z (counter-clockwise), with
// normals unless `with_normals` is false. Returns the mesh index.
int AddQuadMesh(TestGltf* gltf, bool with_normals = true, int material = -1);

std::string Base64(const std::vector<uint8_t>& bytes);
std::vector<uint8_t> PackGlb(const std::string& json, const std::vector<uint8_t>& bin);
std::vector<uint8_t> Bytes(const std::string& s);

absl::StatusOr<Scene> Import(const std::vector<uint8_t>& bytes, const ImportOptions& options = {});

// A PNG containing only a signature, an IHDR of the given size (valid CRC),
// a tiny IDAT and IEND: a header that claims an image it does not hold.
std::vector<uint8_t> PngHeaderOnly(uint32_t width, uint32_t height);

}  // namespace gistream::testing

// Expects `status_or_status` to fail with `code` and a message containing
// `text`.
#define EXPECT_ERROR(expr, expected_code, text)                                \
  do {                                                                         \
    const absl::Status _s = ::gistream::testing::StatusOf(expr);               \
    EXPECT_EQ(_s.code(), absl::StatusCode::expected_code) << _s;               \
    EXPECT_NE(std::string(_s.message()).find(text), std::string::npos)         \
        << "message: " << _s.message() << "\nexpected to contain: " << (text); \
  } while (0)

namespace gistream::testing {
inline absl::Status StatusOf(const absl::Status& s) { return s; }
template <typename T>
absl::Status StatusOf(const absl::StatusOr<T>& s) {
  return s.status();
}
}  // namespace gistream::testing
