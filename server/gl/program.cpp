#include "gl/program.h"

#include <algorithm>
#include <regex>

#include "gl/shader_library.h"
#include "util/log.h"

namespace gistream::gl {
namespace {

// Replaces "0:12(3)" / "0(12)" source-string prefixes with file paths.
std::string Annotate(const std::string& log, const std::vector<std::string>& files) {
  std::string out;
  static const std::regex kPrefix(R"((^|\n)(\d+)([:(]))");
  std::sregex_iterator it(log.begin(), log.end(), kPrefix), end;
  size_t last = 0;
  for (; it != end; ++it) {
    const std::smatch& m = *it;
    const size_t file = std::stoul(m[2].str());
    out += log.substr(last, size_t(m.position(0)) - last);
    out += m[1].str();
    out += file < files.size() ? files[file] : m[2].str();
    out += m[3].str();
    last = size_t(m.position(0) + m.length(0));
  }
  out += log.substr(last);
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ' || out.back() == '\0')) {
    out.pop_back();
  }
  return out;
}

// The info log of a shader or program (glGetShaderiv/glGetShaderInfoLog or
// the program pair).
template <typename GetIv, typename GetLog>
std::string InfoLog(GLuint object, GetIv get_iv, GetLog get_log) {
  GLint length = 0;
  get_iv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 1)), '\0');
  get_log(object, length, nullptr, log.data());
  return log;
}

std::string ShaderLog(GLuint shader) { return InfoLog(shader, glGetShaderiv, glGetShaderInfoLog); }
std::string ProgramLog(GLuint program) {
  return InfoLog(program, glGetProgramiv, glGetProgramInfoLog);
}

}  // namespace

absl::StatusOr<Program> Program::Build(const std::vector<ShaderStage>& stages,
                                       const std::vector<std::string>& defines) {
  Program program;
  program.program_ = ProgramObject::Create();
  std::vector<ShaderObject> shaders;
  std::string names;
  for (const ShaderStage& stage : stages) {
    GS_ASSIGN_OR_RETURN(ExpandedSource source, ExpandShader(stage.path, defines));
    ShaderObject shader = ShaderObject::Create(stage.type);
    const char* text = source.text.c_str();
    glShaderSource(shader.id(), 1, &text, nullptr);
    glCompileShader(shader.id());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
      return absl::InternalError(absl::StrCat("compiling ", stage.path, " failed:\n",
                                              Annotate(ShaderLog(shader.id()), source.files)));
    }
    glAttachShader(program.id(), shader.id());
    program.source_ += source.text;
    absl::StrAppend(&names, names.empty() ? "" : "+", stage.path);
    shaders.push_back(std::move(shader));
  }
  glLinkProgram(program.id());
  GLint ok = GL_FALSE;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  if (!ok) {
    return absl::InternalError(
        absl::StrCat("linking ", names, " failed:\n", ProgramLog(program.id())));
  }
  for (const ShaderObject& shader : shaders) glDetachShader(program.id(), shader.id());
  Label(GL_PROGRAM, program.id(), names.c_str());
  program.name_ = std::move(names);
  return program;
}

GLint Program::Lookup(const char* name) {
  auto it = locations_.find(name);
  if (it != locations_.end()) return it->second;
  const GLint location = glGetUniformLocation(program_.id(), name);
  locations_.emplace(name, location);
  return location;
}

GLint Program::Location(const char* name) {
  const GLint location = Lookup(name);
  if (location < 0 && source_.find(name) == std::string::npos) {
    const std::string message = "GL: " + name_ + " has no active uniform '" + name + "'";
    LogOnce(LogLevel::kWarning, message, message);
  }
  return location;
}

}  // namespace gistream::gl
