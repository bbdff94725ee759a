// Typed buffer creation and upload over the move-only handles: the one
// place that knows GL's buffer-storage rules, so solvers do not keep their
// own MakeBuffer helpers.
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>
#include <type_traits>
#include <vector>

#include "gl/handle.h"

// Checks a C++ mirror of a GLSL std430 struct: trivially copyable, the
// size the shader's layout has, and a multiple of 16 bytes (std430 arrays
// of structs with vec4 members stride by 16). Put it after the struct.
#define GS_STD430_MIRROR(Type, bytes)                                                  \
  static_assert(std::is_trivially_copyable_v<Type>, #Type " is not plain data");       \
  static_assert(sizeof(Type) == (bytes), #Type ": size differs from its GLSL struct"); \
  static_assert(sizeof(Type) % 16 == 0, #Type ": std430 array stride is a multiple of 16")

namespace gistream::gl {

// Immutable storage holding `data` (at least one element, so an empty
// array still binds). flags: glBufferStorage flags (GL_DYNAMIC_STORAGE_BIT
// to allow Upload).
template <typename T>
Buffer StorageBuffer(std::span<const T> data, GLbitfield flags = 0) {
  static_assert(std::is_trivially_copyable_v<T>);
  Buffer buffer = Buffer::Create();
  const T zero{};
  glNamedBufferStorage(buffer.id(), GLsizeiptr(std::max<size_t>(data.size(), 1) * sizeof(T)),
                       data.empty() ? &zero : data.data(), flags);
  return buffer;
}
template <typename T>
Buffer StorageBuffer(const std::vector<T>& data, GLbitfield flags = 0) {
  return StorageBuffer(std::span<const T>(data), flags);
}

// `bytes` (at least 16) of zeros, updatable (GL_DYNAMIC_STORAGE_BIT).
inline Buffer ZeroedBuffer(size_t bytes) {
  Buffer buffer = Buffer::Create();
  glNamedBufferStorage(buffer.id(), GLsizeiptr(std::max<size_t>(bytes, 16)), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  const float zero = 0.0f;
  glClearNamedBufferData(buffer.id(), GL_R32F, GL_RED, GL_FLOAT, &zero);
  return buffer;
}

// Writes `data` at element `first` of a GL_DYNAMIC_STORAGE_BIT buffer.
template <typename T>
void Upload(const Buffer& buffer, std::span<const T> data, size_t first = 0) {
  if (data.empty()) return;
  glNamedBufferSubData(buffer.id(), GLintptr(first * sizeof(T)), GLsizeiptr(data.size_bytes()),
                       data.data());
}

}  // namespace gistream::gl
