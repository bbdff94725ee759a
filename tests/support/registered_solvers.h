// Cross-solver suites and the registry (issue 28): a suite that runs chosen
// cases per solver (its parameters and tolerances) declares which solvers
// it leaves out and why; CoversEveryRegisteredSolver fails when a
// registered solver is neither run nor excused (a new solver cannot miss a
// suite in silence), or when a listed name is no registered solver.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/registry.h"

namespace gistream::testing {

inline std::vector<std::string> RegisteredSolverNames() {
  std::vector<std::string> names;
  for (const SolverDescription& d : AllSolverDescriptions()) names.push_back(d.name);
  return names;
}

// `run`: the solvers the suite's cases name; `excused`: solver -> why not.
inline void ExpectCoversEveryRegisteredSolver(const std::set<std::string>& run,
                                              const std::map<std::string, std::string>& excused) {
  const std::vector<std::string> registered = RegisteredSolverNames();
  for (const std::string& name : registered) {
    EXPECT_TRUE(run.contains(name) || excused.contains(name))
        << name << " is registered but this suite neither runs it nor says why not";
    EXPECT_FALSE(run.contains(name) && excused.contains(name)) << name << " run and excused";
  }
  const std::set<std::string> known(registered.begin(), registered.end());
  for (const std::string& name : run) EXPECT_TRUE(known.contains(name)) << name;
  for (const auto& [name, why] : excused) {
    EXPECT_TRUE(known.contains(name)) << name;
    EXPECT_FALSE(why.empty()) << name;
  }
}

}  // namespace gistream::testing
