// DirectSolver::EstimateMemory and EstimateWork (solvers/memory_estimate.h,
// solvers/work_estimate.h).
#include "solvers/direct/direct_solver.h"

namespace gistream {

MemoryEstimate DirectSolver::EstimateMemory(const ParamSet& params, const SceneState& state,
                                            const GpuScene& gpu) {
  MemoryEstimate estimate;
  estimate.items.push_back(DirectLightingMemory(params, state, gpu, "area_samples", "shadow_res",
                                                /*environment_lights=*/true));
  return estimate;
}

WorkEstimate DirectSolver::EstimateWork(const ParamSet& params, const SceneState& state,
                                        const GpuScene& gpu) {
  WorkEstimate estimate;
  estimate.items.push_back(DirectLightingWork(params, state, gpu));
  return estimate;
}

}  // namespace gistream
