#include "solvers/registry.h"

#include "solvers/antiradiance/antiradiance_solver.h"
#include "solvers/avg/avg_solver.h"
#include "solvers/direct/direct_solver.h"
#include "solvers/implicit_visibility/implicit_visibility_solver.h"
#include "solvers/pathtrace/pathtrace_solver.h"
#include "solvers/sh_probes/sh_probes_solver.h"
#include "util/user_string.h"

namespace gistream {

const std::vector<SolverDescription>& AllSolverDescriptions() {
  static const std::vector<SolverDescription> kAll = {
      DirectSolver::Describe(),   PathtraceSolver::Describe(),
      ShProbesSolver::Describe(), AvgSolver::Describe(),
      ImplicitVisibilitySolver::Describe(), AntiradianceSolver::Describe()};
  return kAll;
}

absl::StatusOr<const SolverDescription*> FindSolver(const std::string& name) {
  std::string known;
  for (const SolverDescription& d : AllSolverDescriptions()) {
    if (d.name == name) return &d;
    absl::StrAppend(&known, known.empty() ? "" : ", ", d.name);
  }
  return absl::InvalidArgumentError(
      absl::StrCat("solver: unknown solver '", Echo(name), "' (known: ", known, ")"));
}

absl::StatusOr<std::unique_ptr<Solver>> CreateSolver(const std::string& name,
                                                     const ParamSet& params) {
  if (name == "direct") return DirectSolver::Create(params);
  if (name == "pathtrace") return PathtraceSolver::Create(params);
  if (name == "sh_probes") return ShProbesSolver::Create(params);
  if (name == "avg") return AvgSolver::Create(params);
  if (name == "implicit_visibility") return ImplicitVisibilitySolver::Create(params);
  if (name == "antiradiance") return AntiradianceSolver::Create(params);
  return FindSolver(name).status();
}

}  // namespace gistream
