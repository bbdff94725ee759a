// DirectSolver::EstimateMemory (solvers/memory_estimate.h).
#include "solvers/direct/direct_solver.h"

namespace gistream {

MemoryEstimate DirectSolver::EstimateMemory(const ParamSet& params, const SceneState& state,
                                            const GpuScene& gpu) {
  MemoryEstimate estimate;
  estimate.items.push_back(DirectLightingMemory(params, state, gpu));
  return estimate;
}

}  // namespace gistream
