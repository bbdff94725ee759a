// A linked GLSL program built from embedded shaders, with cached uniform
// locations. A failed compile or link returns a status carrying the
// driver's log with file names instead of source-string numbers.
#pragma once

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "gl/handle.h"
#include "util/status.h"

namespace gistream::gl {

struct ShaderStage {
  GLenum type;       // GL_VERTEX_SHADER, ...
  std::string path;  // relative to shaders/
};

class Program {
 public:
  Program() = default;
  static absl::StatusOr<Program> Build(const std::vector<ShaderStage>& stages,
                                       const std::vector<std::string>& defines = {});

  GLuint id() const { return program_.id(); }
  void Use() const { glUseProgram(program_.id()); }
  // The uniform's location, cached; -1 when the linked program has no such
  // active uniform. A name that appears nowhere in the program's source (a
  // misspelling, a renamed uniform) is logged once as a warning; one the
  // compiler removed as unused is not.
  GLint Location(const char* name);
  // Sets the uniform when the program has it, silently otherwise: for
  // shared code that feeds several programs (a scene draw, a probe-grid
  // block) of which some do not use every value.
  template <typename T>
  void SetOptional(const char* name, const T& v) {
    if (Lookup(name) >= 0) Set(name, v);
  }

  void Set(const char* name, int v) { glProgramUniform1i(id(), Location(name), v); }
  void Set(const char* name, unsigned v) { glProgramUniform1ui(id(), Location(name), v); }
  void Set(const char* name, float v) { glProgramUniform1f(id(), Location(name), v); }
  void Set(const char* name, const glm::vec2& v) {
    glProgramUniform2f(id(), Location(name), v.x, v.y);
  }
  void Set(const char* name, const glm::vec3& v) {
    glProgramUniform3f(id(), Location(name), v.x, v.y, v.z);
  }
  void Set(const char* name, const glm::vec4& v) {
    glProgramUniform4f(id(), Location(name), v.x, v.y, v.z, v.w);
  }
  void Set(const char* name, const glm::ivec2& v) {
    glProgramUniform2i(id(), Location(name), v.x, v.y);
  }
  void Set(const char* name, const glm::ivec3& v) {
    glProgramUniform3i(id(), Location(name), v.x, v.y, v.z);
  }
  void Set(const char* name, const glm::mat3& m) {
    glProgramUniformMatrix3fv(id(), Location(name), 1, GL_FALSE, &m[0][0]);
  }
  void Set(const char* name, const glm::mat4& m) {
    glProgramUniformMatrix4fv(id(), Location(name), 1, GL_FALSE, &m[0][0]);
  }

 private:
  GLint Lookup(const char* name);  // Location without the warning

  ProgramObject program_;
  std::string name_;    // its shader paths, for messages
  std::string source_;  // the expanded sources, to tell misspelt from unused
  std::unordered_map<std::string, GLint> locations_;
};

}  // namespace gistream::gl
