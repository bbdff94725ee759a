// `implicit_visibility`: Dong, Kautz, Theobalt and Seidel 2007,
// "Interactive Global Illumination Using Implicit Visibility". Hierarchical
// radiosity over vertex discs whose cube-map bins keep only the shortest
// link, so visibility falls out of the link structure. Stages as in the
// paper's Algorithm 1 and Table 1:
//   create_surfels    discs at the vertices (once per mesh, CPU)
//   create_hierarchy  quad-tree clusters by position and normal (once, CPU)
//   update_elements   world discs bottom-up after transforms and deformations (CPU)
//   create_links      top-level pairs, subdivided by bin solid angle (CPU, threads)
//   refine_push       shortest link per bin down each leaf's chain (CPU, threads)
//                     (after a moved node or a deformation both run as a
//                     background job on the CPU pool; frames keep showing
//                     the last solution meanwhile)
//   shadow_maps       the shared direct-light shadow maps (lights, emission, geometry)
//   illumination      direct at leaves, gather + pull per bounce (GL compute)
//   display           vertex irradiance raster + per-pixel direct light
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "render/direct_lighting.h"
#include "solvers/background_job.h"
#include "solvers/job_stage_times.h"
#include "solvers/emission_scale.h"
#include "solvers/hierarchy/bin_table.h"
#include "solvers/hierarchy/cube_bins.h"
#include "solvers/hierarchy/links.h"
#include "solvers/hierarchy/refine_push.h"
#include "solvers/implicit_visibility/display.h"
#include "solvers/implicit_visibility/illumination.h"
#include "solvers/implicit_visibility/scene_elements.h"
#include "solvers/memory_estimate.h"
#include "solvers/work_estimate.h"
#include "solvers/solver.h"
#include "solvers/view_memory.h"

namespace gistream {

struct ImplicitVisibilitySettings {
  int bins_per_face = 12;     // N: 6 x N x N bins per element
  int bounces = 32;           // most indirect bounces (safety cap)
  double tolerance = 0.01;    // stop when a bounce's residual is below this
  bool tail_estimate = true;  // add the bounces not run (solvers/tail_estimate.h)
  int glossy_bins = 128;      // directional bins per glossy element (0: none, illumination.h)
  hierarchy::Linking linking = hierarchy::Linking::kHierarchical;
  DirectLightingSettings direct;
};

class ImplicitVisibilitySolver final : public Solver {
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
  // False while a background relink runs (the shown indirect light is the
  // last solution's) or its illumination has not run yet.
  bool UpdateComplete() const override {
    return !relink_.running() && !relink_.again() && !lighting_.pending();
  }
  bool BackgroundBusy() const override { return relink_.executing(); }
  void CancelBackground() override { relink_.Cancel(); }
  absl::Status Shade(SolverContext& ctx, const ViewCamera& camera, const GBuffer& gbuffer) override;
  SolverStats Stats() const override;
  uint64_t gpu_bytes() const override { return illumination_.gpu_bytes() + lighting_.gpu_bytes(); }

  // Bins of all elements may take at most this much memory.
  static constexpr uint64_t kMaxBinBytes = uint64_t(3) << 30;

 private:
  explicit ImplicitVisibilitySolver(const ImplicitVisibilitySettings& settings)
      : settings_(settings), bins_(settings.bins_per_face) {}

  // Linking of one element layout (create_links + refine_push), on a copy
  // of the elements so it can run on the CPU pool while frames are shaded.
  struct RelinkJob {
    hierarchy::Elements elements;
    bool environment = false;
    uint64_t version = 0;  // the scene version whose geometry it links
    hierarchy::BinTable table;
    hierarchy::LinkStats link_stats;
    hierarchy::LeafLinks leaf_links;
    hierarchy::RefineStats refine_stats;
    JobStageTimes times;  // create_links, refine_push
  };
  absl::Status CheckBinBytes() const;
  // What a change touches (Update's steps read it).
  struct Changed {
    bool first = false;  // nothing built yet
    bool geometry = false, materials = false, lights = false, environment = false;
  };
  void BuildOnce(SolverContext& ctx, bool first);
  absl::Status UpdateElements(SolverContext& ctx, ChangeMask changes, const Changed& changed);
  // A finished relink's links taken (true), stages skipped otherwise.
  bool TakeLinks(SolverContext& ctx, const Changed& changed);
  // While links or shadow maps are pending: the maps in slices; true when
  // both are in and the light is to be gathered now.
  absl::StatusOr<bool> DrawWhilePending(SolverContext& ctx, ChangeMask changes,
                                        const Changed& changed, bool relinked);
  // A pure dimmer rescales the last solution (true) instead of a gather.
  absl::StatusOr<bool> ScaleForDimmer(SolverContext& ctx, ChangeMask changes,
                                      const Changed& changed);
  // The shadow maps and the bounces (stage illumination) when anything
  // changed.
  absl::Status Gather(SolverContext& ctx, ChangeMask changes, const Changed& changed);
  // The first solve and later geometry changes: a background relink (or,
  // while one runs, a note to start another with the newest geometry when
  // it ends).
  absl::Status StartRelink(SolverContext& ctx);
  // Takes a finished background relink's links; true when it did.
  bool FinishRelink(SolverContext& ctx);
  void UpdateEnvironment(const SceneState& state);

  // Configuration
  ImplicitVisibilitySettings settings_;
  hierarchy::CubeBins bins_;

  // Runtime data
  SceneElements scene_;
  hierarchy::BinTable table_;
  hierarchy::LeafLinks leaf_links_;
  DirectLighting lighting_;
  EmissionScale emission_;  // the lights the elements were solved for
  float indirect_scale_ = 1.0f;
  Illumination illumination_;
  Display display_;
  ViewScratch display_memory_;  // display_'s view-sized targets

  bool illumination_stale_ = false;  // an illumination waits for the links
  bool environment_stale_ = false;   // the leaves' environment share waits for it
  bool links_ungathered_ = false;    // links taken since the last gather
  uint64_t gathered_sets_ = 0;       // lighting_.sets_shown() at the last gather
  uint64_t solved_version_ = 0;      // scene version the shown GI reflects
  uint64_t latest_version_ = 0;      // newest scene version seen
  uint64_t links_version_ = 0;       // scene version the links were built for

  // Stats of the last update
  hierarchy::LinkStats link_stats_;
  hierarchy::RefineStats refine_stats_;
  Illumination::Result result_;

  // The background relink; last, so that it is waited for before bins_
  // (which the job reads) is destroyed.
  BackgroundJob<RelinkJob> relink_;
};

}  // namespace gistream
