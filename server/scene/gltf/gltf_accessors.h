// Validated access to glTF accessor data. Nothing is read from a buffer
// until its view and the accessor's whole range have been checked with
// overflow-safe arithmetic.
#pragma once

#include <absl/strings/string_view.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>
#include <vector>

#include "scene/gltf/tinygltf.h"
#include "util/status.h"

namespace gistream::gltf {

// Every buffer view lies inside its buffer.
absl::Status ValidateBufferViews(const tinygltf::Model& model);

// What one use of an accessor requires.
struct AccessorSpec {
  int type = TINYGLTF_TYPE_SCALAR;   // TINYGLTF_TYPE_*
  std::vector<int> component_types;  // allowed TINYGLTF_COMPONENT_TYPE_*
  bool integers_normalized = false;  // integer components must be normalized
};

// A validated accessor: `count` elements, `stride` bytes apart, starting at
// `first`, all inside its buffer.
struct AccessorData {
  int index = -1;
  const uint8_t* first = nullptr;
  uint64_t count = 0;
  uint64_t stride = 0;
  int component_type = 0;
  int components = 0;
  bool normalized = false;
};

// `user` names the referencing field ("meshes[0].primitives[1].indices").
absl::StatusOr<AccessorData> ValidateAccessor(const tinygltf::Model& model, int index,
                                              const AccessorSpec& spec, absl::string_view user);

// Float vectors (FLOAT, or normalized unsigned byte/short); non-finite
// values are refused.
absl::StatusOr<std::vector<glm::vec3>> ReadVec3(const AccessorData& data);
absl::StatusOr<std::vector<glm::vec2>> ReadVec2(const AccessorData& data);

// Every component of every element as floats, element after element:
// FLOAT, or normalized integers (signed per glTF 2.0 3.11: max(c / 127, -1)).
// Non-finite values are refused.
absl::StatusOr<std::vector<float>> ReadFloatComponents(const AccessorData& data);

// Unsigned byte/short VEC4 integers, not normalized (JOINTS_0).
std::vector<glm::u16vec4> ReadU16Vec4(const AccessorData& data);

// Indices, each below `vertex_count`.
absl::StatusOr<std::vector<uint32_t>> ReadIndices(const AccessorData& data, uint64_t vertex_count,
                                                  absl::string_view user);

}  // namespace gistream::gltf
