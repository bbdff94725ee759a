// What a solver tells the world about itself: its name, stages and
// parameter schema (util/params.h).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "util/params.h"

namespace gistream {

struct SolverDescription {
  std::string name;
  std::string description;
  std::vector<std::string> stages;
  std::vector<ParamSpec> params;
};

// ValidateParams against the solver's schema; errors name the solver.
inline absl::StatusOr<ParamSet> ValidateParams(const SolverDescription& solver,
                                               const std::map<std::string, std::string>& given) {
  return ValidateParams("solver '" + solver.name + "'", solver.params, given);
}

}  // namespace gistream
