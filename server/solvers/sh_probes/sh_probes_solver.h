// `sh_probes`: Nijasure, Pattanaik and Goel 2005, "Real-Time Global
// Illumination on GPU". A grid of cube-map probes fitted to the scene
// captures incoming radiance, projected to spherical harmonics; surfaces
// read irradiance by (visibility-weighted) trilinear interpolation; repeated
// for several bounces. Stages as in the paper's Table 1:
//   rasterize_cubemaps  per-probe cube-map G-buffers (geometry changes only)
//   render_cubemaps     shade the stored texels: direct + current indirect
//   sh_project          Eq. 2, per probe, on the GPU
//   interpolate         indirect irradiance at the texels, for the next bounce
//   final               direct + indirect for the view
// After the first solve, a change is solved progressively: a budget of
// probes per frame, the most affected first (solvers/sh_probes/
// probe_schedule.h), blended into the displayed coefficients with
// hysteresis; docs/ARCHITECTURE.md says where that follows DDGI.
#pragma once

#include <vector>

#include "gl/fullscreen_pass.h"
#include "render/direct_lighting.h"
#include "solvers/emission_scale.h"
#include "solvers/moved_bounds.h"
#include "solvers/sh_probes/probe_grid.h"
#include "solvers/sh_probes/probe_raster.h"
#include "solvers/sh_probes/probe_schedule.h"
#include "solvers/tail_estimate.h"
#include "solvers/memory_estimate.h"
#include "solvers/work_estimate.h"
#include "solvers/solver.h"

namespace gistream {

struct ShProbeSettings {
  ProbeGridSettings grid;
  int bands = 3;
  int bounces = 32;
  double tolerance = 0.01;
  bool tail_estimate = true;
  bool indirect_shadows = true;
  double hysteresis = 0.6;  // fraction of the displayed SH kept per frame
  DirectLightingSettings direct;
};

class ShProbesSolver final : public Solver {
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
  // False while the full solve (first, or after a new layout) or a
  // progressive update runs; frames show the latest complete bounce.
  bool UpdateComplete() const override {
    return !full_.active && deferred_ == 0 && !schedule_.pending() && !lighting_.pending();
  }
  // Counts the changes of Shade's inputs: the shown coefficients (a bounce
  // of the first solve, a blend of a change, the converged solution) and
  // the shadow maps (a set shown); the blends of a progressive update after
  // the change are steps while each moves what is shown by at most half
  // the tolerance.
  std::optional<ShownCount> Shown() const override {
    return ShownCount{shown_changes_ + lighting_.sets_shown(), shown_steps_};
  }
  uint64_t gpu_bytes() const override { return atlas_.gpu_bytes() + lighting_.gpu_bytes(); }

 private:
  ShProbesSolver() = default;

  // The first solve, and one after the grid's layout changed: every probe,
  // bounce after bounce (Section 3, Jacobi: a bounce reads the previous
  // one's coefficients), in batches of probes spread over frames by the
  // budget (every batch in one Update when the budget is 0). The batches
  // do what one unsplit pass over all probes does, so the solution does not
  // depend on the split.
  absl::Status StartSolve(SolverContext& ctx, ChangeMask changes, const ProbeLayout& layout);
  absl::Status ContinueSolve(SolverContext& ctx);
  // The current phase of the first solve over `batch`'s probes.
  void RunSolveBatch(SolverContext& ctx, std::vector<int>* batch);
  // The end of a bounce of the first solve: frames show it; the next
  // bounce or FinishSolve.
  void EndSolveBounce(SolverContext& ctx);
  void FinishSolve(SolverContext& ctx);
  // After that: marks what `changes` makes stale and re-renders batches of
  // probes for about the frame budget (ProbeSchedule).
  absl::Status Progress(SolverContext& ctx, ChangeMask changes);
  // Progress's direct light: the shadow maps in slices of the budget; the
  // probes' texels take the new light once it is shown.
  absl::Status ProgressDirectLight(SolverContext& ctx, ChangeMask changes, bool geometry,
                                   bool lights);
  // Progress's geometry change: the probes that see it (all of them for a
  // material change) are re-rasterized, those that see most of it first.
  void ScheduleChangedProbes(SolverContext& ctx, ChangeMask changes);
  // How much of each probe's cube map sees `moved`: the solid angle of the
  // texels whose segments cross it, in micro-steradians (0: none;
  // sees_change.comp.glsl).
  std::vector<int32_t> SeesChange(const Bounds& moved);
  // One batch: rasterize, interpolate, render, project its probes; returns
  // its probes' L_00 change, *total the sum over all valid probes.
  double RunBatch(SolverContext& ctx, const ProbeSchedule::Batch& batch, double* total);
  // After Progress's batches: blends what is shown toward the solution
  // when the frame had a change, the update converged, or the solution
  // moved away from what is shown (unshown_change_).
  void ShowProgress(SolverContext& ctx, bool changed);
  // shown = mix(solution x scale, shown x scale, hysteresis); the solution
  // is scaled too. Counted as a change (Shown), or a step if `step`.
  void Blend(float hysteresis, float scale = 1.0f, bool step = false);

  // `probes` null: every probe; else the listed ones (a batch). From the
  // proxies unless the `full_detail` parameter (ProbeRasterizer).
  void RasterizeCubemaps(const SolverContext& ctx, const std::vector<int>* probes = nullptr);
  void RenderCubemaps(const GpuScene& gpu, bool compute_direct, bool use_indirect,
                      const std::vector<int>* probes = nullptr);
  // Projects, then returns the change of this bounce: the sum over valid
  // probes (of the batch, when given) of |luminance of L_00 - its previous
  // value|; *total gets the sum over all valid probes of |luminance of L_00|.
  double ProjectToSh(double* total, const std::vector<int>* probes = nullptr);
  void Interpolate(const std::vector<int>* probes = nullptr);
  // A texel dispatch over the atlas, or over the listed probes' faces.
  void DispatchTexels(const std::vector<int>* probes) const;
  void ApplyTail(double scale);
  // Binds the grid's uniforms and data with `coefficients` (the solution,
  // or the shown coefficients for Shade).
  void BindProbeData(gl::Program& program, const gl::Buffer& coefficients) const;
  // Uploads the batch list (null: the whole atlas) and sets uBatchCount.
  void SetBatch(gl::Program& program, const std::vector<int>* probes);

  // Configuration
  ShProbeSettings settings_;

  // Runtime data
  DirectLighting lighting_;
  EmissionScale emission_;  // the lights the probes were solved for
  float indirect_scale_ = 1.0f;
  // Shown's counts for shown_coefficients_, and how far the solution is
  // estimated to be from what is shown (relative L_00 change, summed over
  // the batches since, times the hysteresis at each blend).
  uint64_t shown_changes_ = 0;
  uint64_t shown_steps_ = 0;
  double unshown_change_ = 0.0;
  ProbeLayout layout_;
  ProbeAtlas atlas_;
  gl::Buffer coefficients_;           // 9 x probes vec4, coefficient-major: the solution
  gl::Buffer shown_coefficients_;     // what Shade reads (follows the solution, hysteresis)
  gl::Buffer batch_probes_;           // a batch's probe list (ints)
  gl::Buffer sees_change_;            // per probe int, SeesChange's answer (micro-sr)
  gl::Buffer previous_coefficients_;  // the previous bounce's, for the tail
  gl::Buffer probe_valid_;            // probes floats
  std::vector<float> dc_luminance_;   // L_00 luminance per probe, last bounce
  ProbeRasterizer rasterizer_;        // the cube maps, from the proxies unless full_detail
  gl::Program render_, project_, interpolate_, tail_, final_, sees_, blend_;
  gl::FullscreenPass fullscreen_;
  bool solved_ = false;  // a full solve ran (or runs) for layout_
  // The full solve's progress: phase, bounce, next probe of the phase, the
  // bounce's sums so far and each bounce's change (for the tail).
  struct FullSolve {
    enum class Phase { kRaster, kInterpolate, kRender };
    bool active = false;
    Phase phase = Phase::kRaster;
    int bounce = 1;
    int next = 0;
    double change = 0.0, total = 0.0;
    std::vector<double> deltas;
    std::vector<double> totals;  // the solution's sum after each bounce
    bool lights = false;         // the direct light's maps are redrawn first
  } full_;
  ChangeMask deferred_ = 0;   // changes during a full solve, for Progress after it
  ProbeSchedule schedule_;    // the progressive update's probes and sweeps
  MovedBounds moved_;         // the transforms the probes' cube maps saw
  glm::vec3 eye_{0.0f};       // the last shaded camera (probes near it first)
  double ms_per_unit_ = 0.3;  // running cost of a ProbeSchedule unit

  // Stats of the last update
  int bounces_run_ = 0;
  int invalid_probes_ = 0;
  double bounce_change_ = 0.0;
  // TailResidual after the last bounce of a full solve (+inf: none).
  double tail_residual_ = 0.0;
  bool TailSettled() const { return gistream::TailSettled(tail_residual_, settings_.tolerance); }
  bool cap_reached_ = false;
  double tail_ratio_ = 0.0;
  double tail_spread_ = 0.0;
  bool tail_applied_ = false;
  int probes_affected_ = 0;  // probes that saw the last geometry change
  int probes_updated_ = 0;   // probes re-rendered in the last Update
  int batches_run_ = 0;      // and in how many batches
};

}  // namespace gistream
