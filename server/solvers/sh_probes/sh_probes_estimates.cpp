// ShProbesSolver::EstimateMemory and EstimateWork (solvers/memory_estimate.h,
// solvers/work_estimate.h).
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
  // The atlas (probe_grid.h, kAtlasBytesPerTexel).
  estimate.items.push_back({"grid, spacing, face_size",
                            absl::StrCat("probe atlas of ", probes, " probes, ", texels, " texels"),
                            0, texels * kAtlasBytesPerTexel});
  // SH coefficients (solution, previous bounce, shown), validity, the
  // batch list and change flag per probe.
  estimate.items.push_back({"grid, spacing", "SH coefficients", 0, probes * (3 * 9 * 16 + 3 * 4)});
  // The cube maps' draw list, on the CPU and in GL buffers.
  const uint64_t list = ProbeRasterizer::ListBytes(gpu);
  estimate.items.push_back({"", "probe cube draw list", list, list});
  estimate.items.push_back(DirectLightingMemory(params, state, gpu, "area_samples", "shadow_res",
                                                /*environment_lights=*/true));
  return estimate;
}

WorkEstimate ShProbesSolver::EstimateWork(const ParamSet& params, const SceneState& state,
                                          const GpuScene& gpu) {
  ProbeGridSettings grid;
  grid.grid = params.GetInt("grid");
  grid.spacing = float(params.GetFloat("spacing"));
  grid.face_size = params.GetInt("face_size");
  const absl::StatusOr<ProbeLayout> layout = FitProbeGrid(gpu.WorldBounds(state), grid);
  // A layout over the limit is refused by Update; the estimate counts the
  // limit's texels then, as EstimateMemory does.
  const double texels = layout.ok() ? double(layout->texels()) : double(kMaxProbeTexels);
  const double face_texels = std::max(1, grid.face_size * grid.face_size);
  const double faces = layout.ok() ? 6.0 * layout->probes() : texels / face_texels;
  const double triangles = PassTriangles(gpu);
  // A bounce renders every probe's cube from the last bounce's SH, projects
  // it (Section 3, Eq. 3) and interpolates the grid onto the probes'
  // surfaces: 253 ms a bounce for 786K texels on the box (face_size 16),
  // 59 ms at face_size 4: 0.3 us a texel, 12 us a face and each face's
  // draw of the pass's triangles (PassTriangles). One more pass rasterizes
  // the cubes' G-buffers.
  const double bounces = std::max(1, params.GetInt("bounces")) + 1.0;
  const double per_bounce_ns = texels * 300.0 + faces * (12'000.0 + triangles * kTriangleDrawNs);
  WorkEstimate estimate;
  estimate.items.push_back(
      Work("grid, spacing, face_size, bounces",
           absl::StrCat("bounces: ", bounces, " x ", texels, " probe texels and ", faces,
                        " draws of ", triangles, " triangles"),
           bounces, per_bounce_ns));
  estimate.items.push_back(DirectLightingWork(params, state, gpu));
  return estimate;
}

}  // namespace gistream
