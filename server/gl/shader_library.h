// GLSL sources embedded at build time (cmake/EmbedShaders.cmake), with our
// own `#include "path"` expansion and `#line` directives so compile errors
// name the original file and line. Variants are built by prepending
// `#define`s.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "util/status.h"

namespace gistream::gl {

// The text of an embedded file, path relative to shaders/.
absl::StatusOr<std::string_view> EmbeddedShaderSource(std::string_view path);

struct ExpandedSource {
  std::string text;
  std::vector<std::string> files;  // #line source-string number -> path
};

// Expands includes (each file once, like #pragma once), puts `defines`
// right after the #version line.
absl::StatusOr<ExpandedSource> ExpandShader(std::string_view path,
                                            const std::vector<std::string>& defines);

}  // namespace gistream::gl
