// ShProbesSolver::EstimateMemory (solvers/memory_estimate.h).
#include "solvers/sh_probes/sh_probes_solver.h"

namespace gistream {

MemoryEstimate ShProbesSolver::EstimateMemory(const ParamSet& params, const SceneState& state,
                                              const GpuScene& gpu) {
  MemoryEstimate estimate;
  ProbeGridSettings grid;
  grid.grid = params.GetInt("grid");
  grid.spacing = float(params.GetFloat("spacing"));
  grid.face_size = params.GetInt("face_size");
  // A layout over the limit is refused by Update with its own message; the
  // estimate then counts the limit (never more than Update would allow).
  const absl::StatusOr<ProbeLayout> layout = FitProbeGrid(gpu.WorldBounds(state), grid);
  const uint64_t texels = layout.ok() ? layout->texels() : kMaxProbeTexels;
  const uint64_t probes = layout.ok() ? uint64_t(layout->probes()) : kMaxProbeTexels;
  // Atlas per texel: distance R32F, normal RGBA8, albedo RGBA16F, direct
  // and indirect RGBA32F, depth 32 bits (probe_grid.h).
  estimate.items.push_back({"grid, spacing, face_size",
                            absl::StrCat("probe atlas of ", probes, " probes, ", texels, " texels"),
                            0, texels * 52});
  // SH coefficients (solution, previous bounce, shown), validity, the
  // batch list and change flag per probe.
  estimate.items.push_back({"grid, spacing", "SH coefficients", 0, probes * (3 * 9 * 16 + 3 * 4)});
  // The cube maps' draw list, on the CPU and in GL buffers.
  const uint64_t list = ProbeRasterizer::ListBytes(gpu);
  estimate.items.push_back({"", "probe cube draw list", list, list});
  estimate.items.push_back(DirectLightingMemory(params, state, gpu));
  return estimate;
}

}  // namespace gistream
