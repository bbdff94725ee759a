// `pathtrace`: the unbiased reference. A progressive CPU path tracer on
// Embree 3, multi-threaded, independent of the other solvers' code. While
// the scene version and the view are unchanged each frame adds samples to
// the accumulation; any change restarts it.
#pragma once

#include <memory>
#include <vector>

#include "solvers/pathtrace/env_light.h"
#include "solvers/pathtrace/integrator.h"
#include "solvers/pathtrace/scene_bvh.h"
#include "solvers/solver.h"

namespace gistream {

class PathtraceSolver final : public Solver {
 public:
  static SolverDescription Describe();
  static absl::StatusOr<std::unique_ptr<Solver>> Create(const ParamSet& params);

  const SolverDescription& description() const override;
  std::vector<std::string> Plan(ChangeMask changes) const override;
  absl::Status Update(SolverContext& ctx, ChangeMask changes) override;
  absl::Status Shade(SolverContext& ctx, const ViewCamera& camera, const GBuffer& gbuffer) override;
  SolverStats Stats() const override;
  bool NeedsGBuffer() const override { return false; }

 private:
  PathtraceSolver() = default;
  bool SameView(const ViewCamera& camera) const;
  // Traces `spp` more samples per pixel into accum_.
  void TraceRound(const SceneState& state, const ViewCamera& camera, int spp);

  // Configuration
  int spp_per_frame_ = 1;         ///< Samples per pixel added each frame
  double time_budget_ms_ = 0.0;   ///< When > 0: trace 1-spp rounds until spent
  uint64_t seed_ = 0;             ///< Seed of every pixel's random sequence
  pathtrace::IntegratorSettings settings_;

  // Runtime data
  std::unique_ptr<pathtrace::SceneBvh> bvh_;
  std::unique_ptr<pathtrace::EnvironmentLight> env_;  // null: the scene has none
  // The accumulation belongs to one view; the solver instance is shared by
  // every session with these parameters, so a different view restarts it.
  bool has_view_ = false;
  ViewCamera view_;
  std::vector<double> accum_;  // RGB sums, rows bottom first (GL order)
  std::vector<float> image_;   // RGBA averages for upload
  int spp_total_ = 0;
  uint64_t rays_ = 0;       // since the accumulation restarted
  uint64_t last_rays_ = 0;  // traced by the last frame
  uint64_t nonfinite_ = 0;
  double last_trace_ms_ = 0.0;
  int last_spp_ = 0;
};

}  // namespace gistream
