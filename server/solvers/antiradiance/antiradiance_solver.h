// `antiradiance`: Dachsbacher, Stamminger, Drettakis and Durand 2007,
// "Implicit Visibility and Antiradiance for Interactive Global
// Illumination". Light is transported without visibility (operator U);
// antiradiance, propagated the same way, cancels what went through
// occluders. Stages as in the paper's Table 2:
//   link         element hierarchy + link oracle, Section 3.2 (CPU, threads)
//   global_pass  U along the links (CPU, threads)
//   local_pass   direct light into the elements (shadow maps, GPU), K and J (CPU)
//   push_pull    the hierarchy's push / pull (CPU)
//   display      direct per pixel + indirect splatted from the elements (GPU)
// After the first solve, link and transport run as a background job on the
// CPU pool (links of moved roots only) while frames show the last solution.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gl/fullscreen_pass.h"
#include "render/direct_lighting.h"
#include "render/glossy_bin_direct.h"
#include "solvers/background_job.h"
#include "solvers/job_stage_times.h"
#include "solvers/emission_scale.h"
#include "solvers/hierarchy/directional_bins.h"
#include "solvers/antiradiance/glossy_transfer.h"
#include "solvers/antiradiance/links.h"
#include "solvers/antiradiance/patches.h"
#include "solvers/antiradiance/shared_elements.h"
#include "solvers/antiradiance/transport.h"
#include "solvers/memory_estimate.h"
#include "solvers/work_estimate.h"
#include "solvers/solver.h"

namespace gistream {

struct AntiradianceSettings {
  int bins = 128;             // directional bins per element
  float patch_size = 0.0f;    // longest leaf edge (m); 0: scene diagonal / 24
  bool surfels = true;        // elements from the shared hierarchy (vertex discs), else triangles
  bool glossy = true;         // glossy leaves through the BRDF (else every leaf diffuse)
  bool tail_estimate = true;  // add the iterations not run (solvers/tail_estimate.h)
  antiradiance::TransportSettings transport;
  DirectLightingSettings direct;
};

class AntiradianceSolver final : public Solver {
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
  bool UpdateComplete() const override {
    return !solve_.running() && !stale_ && !lighting_.pending();
  }
  bool BackgroundBusy() const override { return solve_.executing(); }
  void CancelBackground() override { solve_.Cancel(); }
  // Shadow maps and the display's element buffer (the transport is CPU memory).
  uint64_t gpu_bytes() const override {
    return lighting_.gpu_bytes() + element_data_.size() * sizeof(glm::vec4) +
           glossy_data_.size() * sizeof(glm::vec4);
  }

 private:
  AntiradianceSolver() = default;

  // Link and transport of one state of the scene (Sections 3.2, 3.3) on
  // copies, run on the CPU pool while frames show the last solution.
  struct SolveJob {
    std::unique_ptr<antiradiance::Patches> patches;  // its address is the transport's
    std::vector<int> leaves;
    antiradiance::LinkSet link_set;
    bool relink = false;            // link the new patches (else keep the links)
    bool same_layout = false;       // relink the moved roots' pairs only
    std::vector<bool> moved;        // per root
    std::vector<glm::vec3> direct;  // E_d per node, at the leaves
    // Glossy leaves (glossy_transfer.h): the BRDF per node, the direct
    // light's exitant radiance per glossy slot and bin, and the matrices
    // (built in the job; the transport refers to them).
    std::vector<shading::Brdf> brdf;
    std::vector<glm::vec3> glossy_direct;
    std::unique_ptr<antiradiance::GlossyTransfer> glossy;
    absl::Status status;  // a limit the links exceed
    std::unique_ptr<antiradiance::Transport> transport;
    antiradiance::TransportResult result;
    JobStageTimes times;  // link and the transport's stages
  };
  // The elements of the scene now; fails (naming the parameter) when their
  // tables would exceed the limits.
  absl::StatusOr<std::unique_ptr<antiradiance::Patches>> PatchesNow(const SolverContext& ctx);
  // Starts a SolveJob: new elements and links when `relink`, the direct
  // light at the leaves from the shadow maps shown now.
  absl::Status StartSolve(const SolverContext& ctx, bool relink);
  // StartSolve's steps: which roots moved since the shown patches (and
  // whether the layout is the same), the leaves' albedo and BRDF from their
  // materials, and the job itself on the CPU pool (link, glossy matrices,
  // transport).
  void FindMovedRoots(SolveJob& job) const;
  void SetLeafMaterials(const SolverContext& ctx, SolveJob& job) const;
  static void RunSolveJob(const hierarchy::DirectionalBins& bins,
                          const antiradiance::TransportSettings& settings,
                          const antiradiance::Transport* warm, SolveJob& job);
  // Shows a finished job's solution (its stage times go to this frame).
  absl::Status TakeSolve(SolverContext& ctx, SolveJob& job);
  // The display's splats and grid for patches_ / leaves_.
  void BuildDisplay();
  // Direct irradiance at the leaves' centres (Section 3.3), per node.
  std::vector<glm::vec3> DirectAtLeaves(const antiradiance::Patches& patches,
                                        const std::vector<int>& leaves);
  void UploadIrradiance();
  // The direct light's exitant radiance per bin at the glossy leaves
  // (slots per node, GlossyTransfer::Slots), glossy slot x bin.
  std::vector<glm::vec3> GlossyDirectAtLeaves(const antiradiance::Patches& patches,
                                              const std::vector<shading::Brdf>& brdf,
                                              const std::vector<int>& slots);

  // Configuration
  AntiradianceSettings settings_;

  // Runtime data
  hierarchy::DirectionalBins bins_;
  std::unique_ptr<antiradiance::Patches> patches_;  // the transport refers to it
  antiradiance::SurfelCache surfel_cache_;
  antiradiance::LinkSet link_set_;
  std::unique_ptr<antiradiance::Transport> transport_;
  std::unique_ptr<antiradiance::GlossyTransfer> glossy_;  // the transport refers to it
  std::vector<int> leaves_;
  DirectLighting lighting_;
  EmissionScale emission_;  // the lights the elements were solved for
  float indirect_scale_ = 1.0f;
  gl::Buffer elements_;  // per leaf: position + splat radius, normal, indirect irradiance
  std::vector<glm::vec4> element_data_;  // its CPU copy, 3 vec4 per leaf
  gl::Buffer grid_;                      // uniform grid over the leaves: cell starts, then leaf ids
  gl::Buffer direct_;                    // per leaf direct irradiance (compute output)
  gl::Buffer bin_directions_;            // the bins' main directions (vec4)
  gl::Buffer glossy_radiance_;           // per glossy slot x bin: reflected indirect radiance
  std::vector<glm::vec4> glossy_data_;   // its CPU copy
  glm::vec3 grid_min_{0.0f};
  glm::ivec3 grid_dims_{1};
  float grid_cell_ = 1.0f;
  float grid_reach_ = 1.0f;  // the largest splat's radius
  gl::Program direct_program_, display_;
  GlossyBinDirect glossy_direct_;  // the glossy leaves' direct light per bin
  gl::FullscreenPass fullscreen_;

  // Stats of the last link / update
  antiradiance::LinkStats link_stats_;
  antiradiance::TransportResult result_;
  double negative_area_ = 0.0;
  double leaf_area_ = 0.0;

  // The solve under way; last, so that it is waited for before the data
  // its job reads (bins_) is destroyed.
  bool started_ = false;     // the first Update ran (its solve may still be running)
  bool stale_ = false;       // a change (or new shadow maps) waits for a solve
  bool relink_due_ = false;  // and it moved geometry
  bool relinking_ = false;   // the running job relinks
  BackgroundJob<SolveJob> solve_;
};

}  // namespace gistream
