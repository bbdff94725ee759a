// `pathtrace`: the unbiased reference. A progressive CPU path tracer on
// Embree 3, multi-threaded, independent of the other solvers' code. While
// the scene version and the view are unchanged each frame adds samples to
// the accumulation; any change restarts it.
#pragma once

#include <memory>
#include <vector>

#include "solvers/shading/env_light.h"
#include "solvers/pathtrace/integrator.h"
#include "solvers/pathtrace/scene_bvh.h"
#include "solvers/memory_estimate.h"
#include "solvers/work_estimate.h"
#include "solvers/solver.h"
#include "solvers/view_memory.h"

namespace gistream {

class PathtraceSolver final : public Solver {
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
  SolverStats Stats() const override;
  bool NeedsGBuffer() const override { return false; }
  bool FrameComplete() const override { return !current_ || current_->frame_complete; }

 private:
  // One view's accumulation. The solver instance is shared by every
  // session with these parameters; each view (camera and size) keeps its
  // own, so sessions that look from different places do not restart each
  // other (their slices interleave).
  struct Accumulation {
    ViewCamera view;
    std::vector<double> accum;  // RGB sums, rows bottom first (GL order)
    int spp_total = 0;          // complete passes
    int pass_row = 0;           // rows of the current pass done (one more sample)
    // What the frame in progress still owes: passes (spp mode) or trace
    // time (time_budget_ms mode, whole passes).
    bool frame_complete = true;
    int owed_passes = 0;
    double frame_trace_ms = 0.0;
    int frame_passes = 0;
    uint64_t frame_rays = 0;
    int frame_slices = 0;  // Shade calls the frame took
    uint64_t rays = 0;     // since the accumulation restarted
    uint64_t nonfinite = 0;
    uint64_t last_used = 0;
    MemoryCharge memory;  // `accum`'s bytes, reserved before it is allocated
  };
  static constexpr size_t kMaxViews = 4;
  // Accumulations of all views together (doubles: 24 bytes a pixel); a
  // view of its own may be larger (the frame-size limit bounds it).
  static constexpr size_t kMaxAccumulationBytes = size_t(1) << 30;

  PathtraceSolver() = default;
  static bool SameView(const ViewCamera& a, const ViewCamera& b);
  // The accumulation of `camera`'s view (least recently used one replaced);
  // a new one is reserved through ctx.reserve first (RESOURCE_EXHAUSTED
  // naming the view's size when refused).
  absl::StatusOr<Accumulation*> ViewFor(const SolverContext& ctx, const ViewCamera& camera);
  // Traces sample `acc.spp_total` of rows [row_begin, row_end).
  void TraceRows(const SceneState& state, Accumulation& acc, int row_begin, int row_end);

  // Configuration
  int spp_per_frame_ = 1;        ///< Samples per pixel added each frame
  double time_budget_ms_ = 0.0;  ///< When > 0: trace 1-spp rounds until spent
  uint64_t seed_ = 0;            ///< Seed of every pixel's random sequence
  pathtrace::IntegratorSettings settings_;

  // Runtime data
  std::unique_ptr<pathtrace::SceneBvh> bvh_;
  uint64_t bvh_rebuilds_ = 0;         // BVH builds since creation (the first included)
  uint64_t bvh_refits_ = 0;           // deformations handled by a refit instead
  uint64_t bvh_refits_declined_ = 0;  // deformations rebuilt: topology or quality
  std::unique_ptr<pathtrace::EnvironmentLight> env_;  // null: the scene has none
  std::vector<Accumulation> views_;
  Accumulation* current_ = nullptr;  // the last shaded view
  uint64_t clock_ = 0;
  std::vector<float> image_;  // RGBA averages for upload
  ViewScratch image_memory_;  // image_'s bytes
  double ms_per_row_ = 0.0;   // per pixel row of a pass, a running estimate; sizes slices
};

}  // namespace gistream
