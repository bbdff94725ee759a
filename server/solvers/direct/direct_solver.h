// `direct`: direct light only. Shadow-mapped punctual lights and emissive
// surfaces sampled at stratified points, each with its own shadow map.
#pragma once

#include "gl/fullscreen_pass.h"
#include "render/direct_lighting.h"
#include "solvers/memory_estimate.h"
#include "solvers/work_estimate.h"
#include "solvers/solver.h"

namespace gistream {

class DirectSolver final : public Solver {
 public:
  static SolverDescription Describe();
  static absl::StatusOr<std::unique_ptr<Solver>> Create(const ParamSet& params);
  // Before Create, from the parameters and the scene (solvers/memory_estimate.h).
  static MemoryEstimate EstimateMemory(const ParamSet& params, const SceneState& state,
                                       const GpuScene& gpu);
  // A complete solve's time at the parameters' caps (solvers/work_estimate.h).
  static WorkEstimate EstimateWork(const ParamSet& params, const SceneState& state,
                                   const GpuScene& gpu);

  const SolverDescription& description() const override;
  std::vector<std::string> Plan(const SceneState& state, ChangeMask changes) const override;
  absl::Status Update(SolverContext& ctx, ChangeMask changes) override;
  absl::Status Shade(SolverContext& ctx, const ViewCamera& camera, const GBuffer& gbuffer) override;
  // False while shadow maps after moved geometry are drawn in slices.
  bool UpdateComplete() const override { return !lighting_.pending(); }
  SolverStats Stats() const override;
  uint64_t gpu_bytes() const override { return lighting_.gpu_bytes(); }

 private:
  DirectSolver() = default;

  // Configuration
  DirectLightingSettings settings_;

  // Runtime data
  DirectLighting lighting_;
  gl::Program shade_;
  gl::FullscreenPass fullscreen_;
};

}  // namespace gistream
