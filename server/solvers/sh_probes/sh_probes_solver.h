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
#pragma once

#include <vector>

#include "render/direct_lighting.h"
#include "solvers/emission_scale.h"
#include "solvers/sh_probes/probe_grid.h"
#include "solvers/memory_estimate.h"
#include "solvers/solver.h"

namespace gistream {

struct ShProbeSettings {
  ProbeGridSettings grid;
  int bands = 3;
  int bounces = 32;
  double tolerance = 0.01;
  bool tail_estimate = false;
  bool indirect_shadows = true;
  DirectLightingSettings direct;
};

class ShProbesSolver final : public Solver {
 public:
  static SolverDescription Describe();
  static absl::StatusOr<std::unique_ptr<Solver>> Create(const ParamSet& params);
  // Before Create, from the parameters and the scene (solvers/memory_estimate.h).
  static MemoryEstimate EstimateMemory(const ParamSet& params, const SceneState& state,
                                       const GpuScene& gpu);

  const SolverDescription& description() const override;
  std::vector<std::string> Plan(ChangeMask changes) const override;
  absl::Status Update(SolverContext& ctx, ChangeMask changes) override;
  absl::Status Shade(SolverContext& ctx, const ViewCamera& camera, const GBuffer& gbuffer) override;
  SolverStats Stats() const override;
  uint64_t gpu_bytes() const override { return atlas_.gpu_bytes() + lighting_.gpu_bytes(); }

 private:
  ShProbesSolver() = default;

  void RasterizeCubemaps(const SolverContext& ctx);
  void RenderCubemaps(bool compute_direct, bool use_indirect);
  // Projects, then returns the change of this bounce: the sum over valid
  // probes of |luminance of L_00 - its previous value|; *total gets the sum
  // of |luminance of L_00|.
  double ProjectToSh(double* total);
  void Interpolate();
  void ApplyTail(double scale);
  void BindProbeData(gl::Program& program) const;

  // Configuration
  ShProbeSettings settings_;

  // Runtime data
  DirectLighting lighting_;
  EmissionScale emission_;  // the lights the probes were solved for
  float indirect_scale_ = 1.0f;
  ProbeLayout layout_;
  ProbeAtlas atlas_;
  gl::Buffer coefficients_;           // 9 x probes vec4, coefficient-major
  gl::Buffer previous_coefficients_;  // the previous bounce's, for the tail
  gl::Buffer probe_valid_;            // probes floats
  std::vector<float> dc_luminance_;   // L_00 luminance per probe, last bounce
  gl::Program rasterize_, render_, project_, interpolate_, tail_, final_;
  gl::VertexArray empty_vao_;

  // Stats of the last update
  int bounces_run_ = 0;
  int invalid_probes_ = 0;
  double bounce_change_ = 0.0;
  bool cap_reached_ = false;
  double tail_ratio_ = 0.0;
  double tail_spread_ = 0.0;
  bool tail_applied_ = false;
};

}  // namespace gistream
