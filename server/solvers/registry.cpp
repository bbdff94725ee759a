#include "solvers/registry.h"

#include <algorithm>
#include <mutex>

#include "util/user_string.h"

namespace gistream {
namespace {

struct Registered {
  SolverFactory factory;
  SolverDescription description;
};

// Filled during static initialisation, frozen (sorted) at the first read.
struct Registry {
  std::vector<Registered> solvers;
  std::vector<SolverDescription> descriptions;
  std::once_flag frozen;
  bool is_frozen = false;
};

Registry& TheRegistry() {
  static Registry registry;
  return registry;
}

const Registry& Frozen() {
  Registry& r = TheRegistry();
  std::call_once(r.frozen, [&r] {
    std::stable_sort(r.solvers.begin(), r.solvers.end(),
                     [](const Registered& a, const Registered& b) {
                       return a.factory.list_order < b.factory.list_order;
                     });
    for (const Registered& s : r.solvers) r.descriptions.push_back(s.description);
    r.is_frozen = true;
  });
  return r;
}

}  // namespace

bool RegisterSolver(const SolverFactory& factory) {
  Registry& r = TheRegistry();
  GS_CHECK(!r.is_frozen && factory.describe && factory.create && factory.estimate);
  SolverDescription description = factory.describe();
  for (const Registered& s : r.solvers) GS_CHECK(s.description.name != description.name);
  r.solvers.push_back({factory, std::move(description)});
  return true;
}

const std::vector<SolverDescription>& AllSolverDescriptions() { return Frozen().descriptions; }

absl::StatusOr<const SolverDescription*> FindSolver(const std::string& name) {
  std::string known;
  for (const SolverDescription& d : AllSolverDescriptions()) {
    if (d.name == name) return &d;
    absl::StrAppend(&known, known.empty() ? "" : ", ", d.name);
  }
  return absl::NotFoundError(
      absl::StrCat("solver: unknown solver '", Echo(name), "' (known: ", known, ")"));
}

absl::StatusOr<std::unique_ptr<Solver>> CreateSolver(const std::string& name,
                                                     const ParamSet& params) {
  for (const Registered& s : Frozen().solvers) {
    if (s.description.name == name) return s.factory.create(params);
  }
  return FindSolver(name).status();
}

absl::StatusOr<MemoryEstimate> EstimateSolverMemory(const std::string& name, const ParamSet& params,
                                                    const SceneState& state, const GpuScene& gpu) {
  for (const Registered& s : Frozen().solvers) {
    if (s.description.name == name) return s.factory.estimate(params, state, gpu);
  }
  return FindSolver(name).status();
}

absl::StatusOr<WorkEstimate> EstimateSolverWork(const std::string& name, const ParamSet& params,
                                                const SceneState& state, const GpuScene& gpu) {
  for (const Registered& s : Frozen().solvers) {
    if (s.description.name == name) return s.factory.estimate_work(params, state, gpu);
  }
  return FindSolver(name).status();
}

}  // namespace gistream
