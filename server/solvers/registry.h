// Every solver gistream offers, in one list.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "solvers/solver.h"

namespace gistream {

const std::vector<SolverDescription>& AllSolverDescriptions();
// NOT_FOUND naming "solver" when unknown.
absl::StatusOr<const SolverDescription*> FindSolver(const std::string& name);
// Creates a solver on the render thread (compiles its programs).
absl::StatusOr<std::unique_ptr<Solver>> CreateSolver(const std::string& name,
                                                     const ParamSet& params);

}  // namespace gistream
