// Move-only RAII handles for GL objects. Id 0 means "no object" (default
// constructed or moved-from); wrap() adopts an existing id, release() gives
// ownership away. Deletion happens on the thread that owns the context,
// which is the only thread that ever holds these.
#pragma once

#include <utility>

#include "gl/gl.h"

namespace gistream::gl {

template <typename Traits>
class Handle {
 public:
  Handle() = default;
  template <typename... Args>
  static Handle Create(Args... args) {
    return Handle(Traits::Create(args...));
  }
  static Handle wrap(GLuint id) { return Handle(id); }

  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  ~Handle() { reset(); }

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  GLuint release() { return std::exchange(id_, 0); }
  void reset() {
    if (id_ != 0) Traits::Delete(id_);
    id_ = 0;
  }

 private:
  explicit Handle(GLuint id) : id_(id) {}
  GLuint id_ = 0;
};

struct BufferTraits {
  static GLuint Create() {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    return id;
  }
  static void Delete(GLuint id) { glDeleteBuffers(1, &id); }
};
struct TextureTraits {
  static GLuint Create(GLenum target) {
    GLuint id = 0;
    glCreateTextures(target, 1, &id);
    return id;
  }
  static void Delete(GLuint id) { glDeleteTextures(1, &id); }
};
struct FramebufferTraits {
  static GLuint Create() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    return id;
  }
  static void Delete(GLuint id) { glDeleteFramebuffers(1, &id); }
};
struct VertexArrayTraits {
  static GLuint Create() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    return id;
  }
  static void Delete(GLuint id) { glDeleteVertexArrays(1, &id); }
};
struct QueryTraits {
  static GLuint Create(GLenum target) {
    GLuint id = 0;
    glCreateQueries(target, 1, &id);
    return id;
  }
  static void Delete(GLuint id) { glDeleteQueries(1, &id); }
};
struct SamplerTraits {
  static GLuint Create() {
    GLuint id = 0;
    glCreateSamplers(1, &id);
    return id;
  }
  static void Delete(GLuint id) { glDeleteSamplers(1, &id); }
};
struct ShaderTraits {
  static GLuint Create(GLenum type) { return glCreateShader(type); }
  static void Delete(GLuint id) { glDeleteShader(id); }
};
struct ProgramTraits {
  static GLuint Create() { return glCreateProgram(); }
  static void Delete(GLuint id) { glDeleteProgram(id); }
};

using Buffer = Handle<BufferTraits>;
using Texture = Handle<TextureTraits>;
using Framebuffer = Handle<FramebufferTraits>;
using VertexArray = Handle<VertexArrayTraits>;
using Query = Handle<QueryTraits>;
using Sampler = Handle<SamplerTraits>;
using ShaderObject = Handle<ShaderTraits>;
using ProgramObject = Handle<ProgramTraits>;

// Sets a KHR_debug label so captures and debug messages name the object.
inline void Label(GLenum identifier, GLuint id, const char* label) {
  glObjectLabel(identifier, id, -1, label);
}

}  // namespace gistream::gl
