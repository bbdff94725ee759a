#include "solver_list.h"

#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>

#include "text_table.h"

namespace gistream::client {
namespace {

absl::string_view TypeName(v1::ParamType type) {
  switch (type) {
    case v1::PARAM_TYPE_INT: return "int";
    case v1::PARAM_TYPE_FLOAT: return "float";
    case v1::PARAM_TYPE_BOOL: return "bool";
    case v1::PARAM_TYPE_ENUM: return "enum";
    default: return "?";
  }
}

}  // namespace

std::string FormatParamRange(const v1::ParamSpec& param) {
  switch (param.type()) {
    case v1::PARAM_TYPE_BOOL: return "true|false";
    case v1::PARAM_TYPE_ENUM: return absl::StrJoin(param.choices(), "|");
    case v1::PARAM_TYPE_INT:
    case v1::PARAM_TYPE_FLOAT:
      if (param.min() == 0.0 && param.max() == 0.0) return "-";
      return absl::StrCat("[", param.min(), ", ", param.max(), "]");
    default: return "-";
  }
}

std::string FormatSolverList(const v1::ListSolversResponse& solvers) {
  std::string out;
  for (const v1::SolverInfo& solver : solvers.solvers()) {
    if (!out.empty()) out += "\n";
    absl::StrAppend(&out, solver.name(), solver.description().empty() ? "" : " - ",
                    solver.description(), "\n");
    absl::StrAppend(&out, "  stages: ",
                    solver.stages().empty() ? "none" : absl::StrJoin(solver.stages(), ", "), "\n");
    if (solver.params().empty()) {
      out += "  parameters: none\n";
      continue;
    }
    out += "  parameters:\n";
    TextTable table({{"name"}, {"type"}, {"default"}, {"range"}, {"meaning"}});
    for (const v1::ParamSpec& param : solver.params()) {
      table.AddRow({param.name(), std::string(TypeName(param.type())), param.default_value(),
                    FormatParamRange(param), param.description()});
    }
    out += table.Render("    ");
  }
  if (out.empty()) out = "the server offers no solvers\n";
  return out;
}

}  // namespace gistream::client
