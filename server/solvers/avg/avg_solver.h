// `avg`: instant radiosity with VPLs traced through an approximate
// visibility grid (Bashford-Rogers et al., "Approximate Visibility Grids
// for Interactive Indirect Illumination"). Stages: voxelize (CPU),
// trace_vpls (CPU), vpl_shadow_maps, gbuffer (the engine's), illuminate,
// filter. Direct light comes from the shared DirectLighting (shadow-mapped
// punctual lights and area-light samples); VPLs carry the indirect bounces.
// After the first solve, voxelize and trace_vpls run as a background job on
// the CPU pool, on a copy of the scene state, while frames show the last
// VPLs and maps; the frame that takes the job starts the (sliced) re-map.
#pragma once

#include <memory>
#include <optional>

#include "gl/fullscreen_pass.h"
#include "render/direct_lighting.h"
#include "solvers/background_job.h"
#include "solvers/job_stage_times.h"
#include "solvers/avg/interleaved_buffer.h"
#include "solvers/avg/voxel_grid.h"
#include "solvers/avg/vpl_shadow_maps.h"
#include "solvers/avg/vpl_tracer.h"
#include "solvers/memory_estimate.h"
#include "solvers/work_estimate.h"
#include "solvers/moved_bounds.h"
#include "solvers/solver.h"
#include "solvers/view_memory.h"

namespace gistream {

class AvgSolver final : public Solver {
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
  // False while a background voxelize + trace runs (or another is due) and
  // while new VPLs' maps are drawn in slices (frames show the last VPLs
  // and maps meanwhile).
  // A still view's second set of paths (`still_vpls`) is part of the
  // solution: false until it is traced and mapped.
  bool UpdateComplete() const override {
    return !trace_job_.running() && !trace_job_.again() && !remap_pending_ && !direct_.pending() &&
           !extend_job_.running() && !ExtensionDue();
  }
  bool BackgroundBusy() const override { return trace_job_.executing() || extend_job_.executing(); }
  void CancelBackground() override {
    trace_job_.Cancel();
    extend_job_.Cancel();
  }
  // VPL and direct-light shadow maps, both atlases (the voxel grid is CPU memory).
  uint64_t gpu_bytes() const override {
    return shadow_maps_.gpu_bytes() + remap_.gpu_bytes() + direct_.gpu_bytes();
  }

  // For tests: the current grid and VPLs (the grid and paths are the
  // running job's, so null and empty, while a background trace runs; the
  // VPLs are the last taken trace's).
  const avg::VoxelGrid* grid() const { return grid_ ? &*grid_ : nullptr; }
  const avg::VplTraceResult& vpls() const { return trace_; }
  const avg::VplPathCache& paths() const { return paths_; }

 private:
  static bool SamePlacement(const std::vector<avg::Vpl>& a, const std::vector<avg::Vpl>& b);
  AvgSolver() = default;
  // What a change set needs, as flags.
  static bool NeedsVoxelize(ChangeMask changes);
  static bool NeedsTrace(ChangeMask changes);

  // Voxelize (what moved, or the whole grid) and trace_vpls of one scene
  // state, on a copy of it, on the CPU pool while frames are shaded from
  // the last VPLs and maps. The grid and path cache move into the job and
  // back when it is taken (nothing else reads them meanwhile).
  struct TraceJob {
    explicit TraceJob(const SceneState& s) : state(s) {}
    SceneState state;        // the snapshot (posed meshes shared copy-on-write)
    ChangeMask changes = 0;  // what changed since the last job's snapshot
    bool voxelize = false;
    bool rebuild = false;  // Build the whole grid (else Revoxelize `moved`)
    Bounds moved;          // moved primitives' old and new boxes
    float clamp_distance = 0.0f;
    std::optional<avg::VoxelGrid> grid;  // in: the last grid (none at first); out: the new one
    avg::VplPathCache paths;             // in: the last trace's paths; out: this trace's
    // Results
    bool partial = false;  // only the moved box was voxelized (grid->rewritten())
    double voxels_rewritten = 0;
    Bounds grid_bounds;
    avg::VplTraceResult trace;
    // A still view's VPLs traced again with a light change: trace joined
    // with its second set (TakeTrace keeps it where no VPL moved).
    std::optional<avg::VplTraceResult> joined;
    JobStageTimes times;  // voxelize, trace_vpls
  };
  // A still view's second set of paths (`still_vpls`, Keller's instant
  // radiosity refined progressively): once the shown VPLs are the latest
  // and nothing is due, still_vpls - vpls more VPLs are traced on the CPU
  // pool, going on with the shown paths' quasi-random sequence, from the
  // shown grid (read only: no trace job runs meanwhile, and a change
  // cancels this one); joined to the shown VPLs (avg::JoinTraces) and
  // mapped like a trace's (the shown maps copied). Motion never waits for
  // it: a change cancels it, and the next trace is of vpls again.
  struct ExtendJob {
    explicit ExtendJob(const SceneState& s) : state(s) {}
    SceneState state;                      // for the lights
    const avg::VoxelGrid* grid = nullptr;  // grid_, read only
    Bounds grid_bounds;                    // the shown maps'
    avg::VplTraceResult base;              // the shown VPLs
    avg::VplTraceResult trace;             // out: base and the second set, joined
    JobStageTimes times;                   // trace_vpls
  };
  bool ExtensionDue() const { return still_vpls_ > trace_settings_.vpls && traced_ && !extended_; }
  void StartExtension(const SolverContext& ctx);
  void TakeExtension(SolverContext& ctx, ExtendJob& job);

  // Starts a job for the changes due (the caller checks that none runs).
  void StartTrace(const SolverContext& ctx);
  // Shows a finished job's VPLs (their maps drawn in slices from this
  // frame on); its stage times go to this frame.
  void TakeTrace(SolverContext& ctx, TraceJob& job);
  // Notes geometry changed since the shown maps (and a re-map's) were drawn.
  void NoteGeometryChange(const Bounds& moved, bool everywhere);
  // Starts drawing trace_'s VPL maps into remap_: the maps of shown VPLs
  // that stayed where they were and cannot see geometry changed since the
  // shown maps were drawn are copied, the others queued for drawing.
  void StartRemap(SolverContext& ctx, const Bounds& grid_bounds);
  // Draws the next slice of the re-map (as many maps as the budget allows,
  // at least one); when the last is drawn, the new VPLs and maps are shown.
  void ContinueRemap(SolverContext& ctx);

  // Configuration
  int grid_resolution_ = 64;              ///< voxels per axis
  avg::VplTraceSettings trace_settings_;  ///< vpls, bounces, roulette
  bool tail_estimate_ = true;             ///< the generations `bounces` leaves out
  int shadow_resolution_ = 64;            ///< VPL paraboloid map size
  bool visibility_ = true;                ///< false: VPLs unshadowed
  float clamp_ = 0.0f;                    ///< geometry-term bias, fraction of the scene diagonal
  int still_vpls_ = 2048;                 ///< VPLs of a still view's solution (ExtendJob)
  DirectLightingSettings direct_settings_;

  // Runtime data
  std::optional<avg::VoxelGrid> grid_;
  MovedBounds moved_;            // the transforms the last job voxelized
  bool traced_ = false;          // the first solve is done
  bool started_ = false;         // the first voxelize + trace was started
  ChangeMask due_ = 0;           // changes the next job must cover
  bool job_voxelizes_ = false;   // the running job voxelizes
  uint64_t latest_version_ = 0;  // newest scene version seen
  uint64_t shown_version_ = 0;   // scene version the shown VPLs and maps reflect
  uint64_t remap_version_ = 0;   // ... and the ones being re-mapped
  size_t voxels_filled_ = 0;     // the last taken grid's
  uint64_t voxel_bytes_ = 0;
  avg::VplTraceResult trace_;
  avg::VplPathCache paths_;  // trace_'s paths, for the next incremental trace
  // The VPLs whose paraboloid maps are drawn (each path's first layer, the
  // grid box their far planes came from), and how many the last update drew.
  std::vector<avg::Vpl> mapped_vpls_;
  std::vector<uint32_t> mapped_path_first_;
  Bounds mapped_bounds_;
  // Geometry changed since the shown maps were drawn (`unmapped_all_`: by
  // more than a known box).
  Bounds unmapped_change_;
  bool unmapped_all_ = true;
  // ... since the re-map under way started: its maps may predate it.
  Bounds remap_change_;
  bool remap_all_ = false;
  int vpl_maps_redrawn_ = 0;
  int vpl_maps_kept_ = 0;           // copied from the shown atlas by the last re-map
  bool voxels_partial_ = false;     // the last voxelize rewrote a box only
  double voxels_rewritten_ = 0;     // voxels it cleared and re-rasterized
  avg::VplShadowMaps shadow_maps_;  // shown: VPLs and maps that agree
  // New VPLs whose maps are being drawn, in slices of the frame budget.
  avg::VplShadowMaps remap_;
  std::vector<avg::Vpl> remap_vpls_;
  std::vector<uint32_t> remap_path_first_;
  Bounds remap_bounds_;
  std::vector<int> remap_layers_;  // the layers to draw, in order
  bool remap_pending_ = false;
  int remap_next_ = 0;
  double ms_per_map_ = 0.0;   // running estimate, sizes the slices
  bool full_detail_ = false;  // voxelize and draw shadow maps from the full meshes
  DirectLighting direct_;
  avg::InterleavedBuffer split_;
  ViewScratch split_memory_;  // split_'s bytes, reserved before it grows
  gl::Program illuminate_;
  gl::Program filter_;
  gl::FullscreenPass fullscreen_;
  float clamp_distance_ = 0.0f;  // world units
  bool extended_ = false;        // the shown VPLs include a still view's second set
  size_t still_vpls_shown_ = 0;  // the second set's VPLs shown

  // The background voxelize + trace; last, so that it is waited for
  // before the rest of the solver is destroyed.
  BackgroundJob<TraceJob> trace_job_;
  // Reads grid_: after it, so that it is waited for first.
  BackgroundJob<ExtendJob> extend_job_;
};

}  // namespace gistream
