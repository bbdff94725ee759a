// Every solver gistream offers. Each solver registers itself from its own
// file with GISTREAM_REGISTER_SOLVER, so adding one touches no other file:
//
//   // solvers/my_solver/my_solver.cpp
//   GISTREAM_REGISTER_SOLVER(MySolver, 70);
//
// where MySolver has `static SolverDescription Describe()` and
// `static absl::StatusOr<std::unique_ptr<Solver>> Create(const ParamSet&)`,
// and 70 is its place in listings (direct 10, pathtrace 20, sh_probes 30,
// avg 40, implicit_visibility 50, antiradiance 60). The solvers library is
// linked whole (CMake WHOLE_ARCHIVE), so no registration is dropped.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "solvers/memory_estimate.h"
#include "solvers/solver.h"
#include "solvers/work_estimate.h"

namespace gistream {

struct SolverFactory {
  SolverDescription (*describe)() = nullptr;
  absl::StatusOr<std::unique_ptr<Solver>> (*create)(const ParamSet&) = nullptr;
  int list_order = 0;
  // What Create will allocate (solvers/memory_estimate.h), checked by the
  // engine against the memory budget before it calls Create.
  MemoryEstimate (*estimate)(const ParamSet&, const SceneState&, const GpuScene&) = nullptr;
  // A complete solve's time (solvers/work_estimate.h), checked by the engine
  // against --max-solve-seconds before it calls Create.
  WorkEstimate (*estimate_work)(const ParamSet&, const SceneState&, const GpuScene&) = nullptr;
};

// Called by GISTREAM_REGISTER_SOLVER during static initialisation; aborts
// on a duplicate name or a registration after the list was first read.
bool RegisterSolver(const SolverFactory& factory);

#define GISTREAM_REGISTER_SOLVER(Class, list_order)                               \
  [[maybe_unused]] static const bool kRegistered##Class =                         \
      ::gistream::RegisterSolver({&Class::Describe, &Class::Create, (list_order), \
                                  &Class::EstimateMemory, &Class::EstimateWork})

// The registered solvers by list order.
const std::vector<SolverDescription>& AllSolverDescriptions();
// NOT_FOUND naming "solver" (and the known names) when unknown.
absl::StatusOr<const SolverDescription*> FindSolver(const std::string& name);
// Creates a solver on the render thread (compiles its programs); NOT_FOUND
// as FindSolver.
absl::StatusOr<std::unique_ptr<Solver>> CreateSolver(const std::string& name,
                                                     const ParamSet& params);
// The solver's memory estimate for `params` on the scene as it is now;
// NOT_FOUND as FindSolver.
absl::StatusOr<MemoryEstimate> EstimateSolverMemory(const std::string& name, const ParamSet& params,
                                                    const SceneState& state, const GpuScene& gpu);
// The solver's solve-time estimate, likewise.
absl::StatusOr<WorkEstimate> EstimateSolverWork(const std::string& name, const ParamSet& params,
                                                const SceneState& state, const GpuScene& gpu);

}  // namespace gistream
