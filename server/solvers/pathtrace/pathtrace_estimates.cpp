// PathtraceSolver::EstimateMemory and EstimateWork (solvers/memory_estimate.h,
// solvers/work_estimate.h).
#include "solvers/pathtrace/pathtrace_solver.h"

namespace gistream {

MemoryEstimate PathtraceSolver::EstimateMemory(const ParamSet& /*params*/, const SceneState& state,
                                               const GpuScene& /*gpu*/) {
  MemoryEstimate estimate;
  // Embree's BVH over world-space copies of the triangles: about 128 bytes
  // per triangle (build primitives, nodes, vertex and index copies).
  const InstancedCounts counts = CountInstanced(state);
  estimate.items.push_back({"", absl::StrCat("ray-tracing BVH of ", counts.triangles, " triangles"),
                            counts.triangles * 128 + counts.vertices * 16, 0});
  // The environment's sampling tables: a CDF entry per pixel.
  if (const auto& env = state.scene().environment) {
    const uint64_t pixels = uint64_t(env->image.width) * uint64_t(env->image.height);
    estimate.items.push_back({"", "environment sampling tables", pixels * 8, 0});
  }
  // The per-view accumulation buffers (24 bytes a pixel) and the image
  // upload buffer (16 bytes a pixel) are view-dependent: the solver reserves
  // them when a view needs them (SolverContext::reserve), and its caps
  // (kMaxViews, kMaxAccumulationBytes) still apply.
  return estimate;
}

WorkEstimate PathtraceSolver::EstimateWork(const ParamSet& /*params*/, const SceneState& /*state*/,
                                           const GpuScene& /*gpu*/) {
  // Nothing up front: the paths are traced in slices of the frame budget
  // (--frame-budget-ms), a view's samples accumulate frame by frame, and a
  // Render that waits for `spp` samples is bounded by its deadline. What a
  // complete image costs depends on the view (pixels x spp), which a
  // session sets after the solver is built.
  return {};
}

}  // namespace gistream
