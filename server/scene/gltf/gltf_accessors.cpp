#include "scene/gltf/gltf_accessors.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "scene/gltf/gltf_util.h"

namespace gistream::gltf {
namespace {

static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian");

absl::string_view ComponentName(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return "DOUBLE";
  }
  return "unknown";
}

absl::string_view TypeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
  }
  return "unknown";
}

std::string AllowedComponents(const std::vector<int>& types) {
  std::string out;
  for (int t : types) absl::StrAppend(&out, out.empty() ? "" : " or ", ComponentName(t));
  return out;
}

// Component j of element i as a float (integers normalized when asked).
float Component(const AccessorData& d, uint64_t i, int j) {
  const uint8_t* p = d.first + i * d.stride;
  switch (d.component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p + 4 * j, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return static_cast<float>(p[j]) / 255.0f;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p + 2 * j, 2);
      return static_cast<float>(v) / 65535.0f;
    }
    // Signed normalized (animation outputs only): glTF 2.0 3.11.
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return std::max(static_cast<float>(static_cast<int8_t>(p[j])) / 127.0f, -1.0f);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p + 2 * j, 2);
      return std::max(static_cast<float>(v) / 32767.0f, -1.0f);
    }
  }
  CheckFailed(__FILE__, __LINE__, "component type not admitted by ValidateAccessor");
}

absl::StatusOr<std::vector<float>> ReadFloats(const AccessorData& d, int n) {
  GS_CHECK(d.components == n);
  std::vector<float> out(d.count * static_cast<uint64_t>(n));
  for (uint64_t i = 0; i < d.count; ++i) {
    for (int j = 0; j < n; ++j) {
      const float v = Component(d, i, j);
      if (!std::isfinite(v)) {
        return absl::InvalidArgumentError(absl::StrCat(Item("accessors", d.index), ": element ", i,
                                                       " component ", j, " is ", v,
                                                       ", not a finite number"));
      }
      out[i * static_cast<uint64_t>(n) + static_cast<uint64_t>(j)] = v;
    }
  }
  return out;
}

}  // namespace

absl::Status ValidateBufferViews(const tinygltf::Model& model) {
  for (size_t i = 0; i < model.bufferViews.size(); ++i) {
    const tinygltf::BufferView& view = model.bufferViews[i];
    const std::string field = Item("bufferViews", i);
    GS_RETURN_IF_ERROR(CheckIndex(field + ".buffer", view.buffer, model.buffers.size(), "buffers"));
    if (view.byteLength == 0) {
      return absl::InvalidArgumentError(field + ".byteLength: 0 (must be at least 1)");
    }
    const uint64_t size = model.buffers[size_t(view.buffer)].data.size();
    uint64_t end = 0;
    if (!MulAdd(1, view.byteOffset, view.byteLength, &end) || end > size) {
      return absl::InvalidArgumentError(absl::StrCat(
          field, ".byteLength: ", view.byteLength, " bytes at byteOffset ", view.byteOffset,
          " overrun ", Item("buffers", view.buffer), " (byteLength ", size, ")"));
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<AccessorData> ValidateAccessor(const tinygltf::Model& model, int index,
                                              const AccessorSpec& spec, absl::string_view user) {
  GS_RETURN_IF_ERROR(CheckIndex(user, index, model.accessors.size(), "accessors"));
  const tinygltf::Accessor& a = model.accessors[size_t(index)];
  const std::string field = Item("accessors", index);
  if (a.type != spec.type) {
    return absl::InvalidArgumentError(absl::StrCat(field, ".type: ", TypeName(a.type), " but ",
                                                   user, " needs ", TypeName(spec.type)));
  }
  bool allowed = false;
  for (int t : spec.component_types) allowed = allowed || t == a.componentType;
  if (!allowed) {
    return absl::InvalidArgumentError(absl::StrCat(
        field, ".componentType: ", a.componentType, " (", ComponentName(a.componentType), ") but ",
        user, " needs ", AllowedComponents(spec.component_types)));
  }
  if (spec.integers_normalized && a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT &&
      !a.normalized) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ".normalized: integer data for ", user, " must be normalized"));
  }
  if (a.sparse.isSparse) {
    return absl::InvalidArgumentError(field + ".sparse: sparse accessors are not supported");
  }
  if (a.bufferView < 0) {
    return absl::InvalidArgumentError(
        field + ".bufferView: missing (accessors without data are not supported)");
  }
  GS_RETURN_IF_ERROR(
      CheckIndex(field + ".bufferView", a.bufferView, model.bufferViews.size(), "bufferViews"));
  if (a.count == 0) return absl::InvalidArgumentError(field + ".count: 0 (must be at least 1)");

  const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
  const uint64_t component_size =
      static_cast<uint64_t>(tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType)));
  const uint64_t components =
      static_cast<uint64_t>(tinygltf::GetNumComponentsInType(uint32_t(a.type)));
  const uint64_t element_size = component_size * components;
  const uint64_t stride = view.byteStride != 0 ? view.byteStride : element_size;
  const std::string view_field = Item("bufferViews", a.bufferView);
  if (stride < element_size || stride % component_size != 0) {
    return absl::InvalidArgumentError(absl::StrCat(view_field, ".byteStride: ", stride,
                                                   " does not fit the ", element_size,
                                                   "-byte elements of ", field));
  }
  if (a.byteOffset >= view.byteLength) {
    return absl::InvalidArgumentError(absl::StrCat(field, ".byteOffset: ", a.byteOffset,
                                                   " is past the end of ", view_field,
                                                   " (byteLength ", view.byteLength, ")"));
  }
  uint64_t end = 0;
  if (!MulAdd(stride, a.count - 1, element_size, &end) || !MulAdd(1, end, a.byteOffset, &end) ||
      end > view.byteLength) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ".count: ", a.count, " elements of ", element_size, " bytes (stride ",
                     stride, ") from byteOffset ", a.byteOffset, " overrun ", view_field,
                     " (byteLength ", view.byteLength, ")"));
  }
  // ValidateBufferViews has checked the view against its buffer.
  const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
  AccessorData d;
  d.index = index;
  d.first = buffer.data() + view.byteOffset + a.byteOffset;
  d.count = a.count;
  d.stride = stride;
  d.component_type = a.componentType;
  d.components = static_cast<int>(components);
  d.normalized = a.normalized;
  return d;
}

absl::StatusOr<std::vector<glm::vec3>> ReadVec3(const AccessorData& data) {
  GS_ASSIGN_OR_RETURN(const std::vector<float> f, ReadFloats(data, 3));
  std::vector<glm::vec3> out(data.count);
  for (uint64_t i = 0; i < data.count; ++i) out[i] = {f[3 * i], f[3 * i + 1], f[3 * i + 2]};
  return out;
}

absl::StatusOr<std::vector<glm::vec2>> ReadVec2(const AccessorData& data) {
  GS_ASSIGN_OR_RETURN(const std::vector<float> f, ReadFloats(data, 2));
  std::vector<glm::vec2> out(data.count);
  for (uint64_t i = 0; i < data.count; ++i) out[i] = {f[2 * i], f[2 * i + 1]};
  return out;
}

absl::StatusOr<std::vector<float>> ReadFloatComponents(const AccessorData& data) {
  return ReadFloats(data, data.components);
}

std::vector<glm::u16vec4> ReadU16Vec4(const AccessorData& d) {
  GS_CHECK(d.components == 4);
  std::vector<glm::u16vec4> out(d.count);
  for (uint64_t i = 0; i < d.count; ++i) {
    const uint8_t* p = d.first + i * d.stride;
    for (int j = 0; j < 4; ++j) {
      if (d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        out[i][j] = p[j];
      } else {
        GS_CHECK(d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
        uint16_t v;
        std::memcpy(&v, p + 2 * j, 2);
        out[i][j] = v;
      }
    }
  }
  return out;
}

absl::StatusOr<std::vector<uint32_t>> ReadIndices(const AccessorData& d, uint64_t vertex_count,
                                                  absl::string_view user) {
  GS_CHECK(d.components == 1);
  std::vector<uint32_t> out(d.count);
  for (uint64_t i = 0; i < d.count; ++i) {
    const uint8_t* p = d.first + i * d.stride;
    uint32_t v = 0;
    switch (d.component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = p[0]; break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t s;
        std::memcpy(&s, p, 2);
        v = s;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: std::memcpy(&v, p, 4); break;
      default: CheckFailed(__FILE__, __LINE__, "index type not admitted by ValidateAccessor");
    }
    if (v >= vertex_count) {
      return absl::InvalidArgumentError(
          absl::StrCat(user, " (", Item("accessors", d.index), "): index ", v, " at position ", i,
                       " is out of range (", vertex_count, " vertices)"));
    }
    out[i] = v;
  }
  return out;
}

}  // namespace gistream::gltf
