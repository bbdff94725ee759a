#include "gl/shader_library.h"

#include <set>
#include <sstream>

namespace gistream {
struct EmbeddedShader {
  const char* path;
  const char* text;
};
extern const EmbeddedShader kEmbeddedShaders[];
extern const int kEmbeddedShaderCount;
}  // namespace gistream

namespace gistream::gl {

absl::StatusOr<std::string_view> EmbeddedShaderSource(std::string_view path) {
  for (int i = 0; i < kEmbeddedShaderCount; ++i) {
    if (path == kEmbeddedShaders[i].path) return std::string_view(kEmbeddedShaders[i].text);
  }
  return absl::NotFoundError(absl::StrCat("shader '", std::string(path), "' is not embedded"));
}

namespace {

absl::Status Expand(std::string_view path, int depth, std::set<std::string>& seen,
                    ExpandedSource& out) {
  if (depth > 16)
    return absl::InternalError(absl::StrCat(std::string(path), ": #include nested too deep"));
  GS_ASSIGN_OR_RETURN(std::string_view text, EmbeddedShaderSource(path));
  const int file_number = int(out.files.size());
  out.files.emplace_back(path);
  std::istringstream lines{std::string(text)};
  std::string line;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    const size_t start = line.find_first_not_of(" \t");
    if (start != std::string::npos && line.compare(start, 8, "#include") == 0) {
      const size_t open = line.find('"', start);
      const size_t close = open == std::string::npos ? open : line.find('"', open + 1);
      if (close == std::string::npos) {
        return absl::InternalError(
            absl::StrCat(std::string(path), ":", line_number, ": malformed #include"));
      }
      const std::string target = line.substr(open + 1, close - open - 1);
      if (seen.insert(target).second) {
        GS_RETURN_IF_ERROR(Expand(target, depth + 1, seen, out));
      }
      out.text += absl::StrCat("#line ", line_number + 1, " ", file_number, "\n");
      continue;
    }
    out.text += line;
    out.text += '\n';
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<ExpandedSource> ExpandShader(std::string_view path,
                                            const std::vector<std::string>& defines) {
  GS_ASSIGN_OR_RETURN(std::string_view text, EmbeddedShaderSource(path));
  // The #version line must come first; defines follow it.
  const size_t eol = text.find('\n');
  const std::string_view first = text.substr(0, eol);
  if (first.rfind("#version", 0) != 0) {
    return absl::InternalError(absl::StrCat(std::string(path), ": first line must be #version"));
  }
  ExpandedSource out;
  out.text = std::string(first) + "\n";
  for (const std::string& d : defines) out.text += absl::StrCat("#define ", d, "\n");
  out.text += "#line 2 0\n";
  std::set<std::string> seen{std::string(path)};
  ExpandedSource body;
  GS_RETURN_IF_ERROR(Expand(path, 0, seen, body));
  // Drop the body's own #version line (the first line of the root file).
  const size_t body_eol = body.text.find('\n');
  out.text += body.text.substr(body_eol + 1);
  out.files = std::move(body.files);
  return out;
}

}  // namespace gistream::gl
