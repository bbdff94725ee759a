// AvgSolver::EstimateMemory (solvers/memory_estimate.h).
#include <algorithm>

#include "solvers/avg/avg_solver.h"
#include "solvers/avg/vpl_shadow_maps.h"
#include "scene/gpu/draw_list.h"

namespace gistream {

MemoryEstimate AvgSolver::EstimateMemory(const ParamSet& params, const SceneState& state,
                                         const GpuScene& gpu) {
  const uint64_t vpls = uint64_t(std::max(0, params.GetInt("vpls")));
  const uint64_t res = uint64_t(std::max(0, params.GetInt("shadow_res")));
  const uint64_t grid = uint64_t(std::max(0, params.GetInt("grid")));
  MemoryEstimate estimate;
  if (params.GetBool("visibility")) {
    // Two paraboloid atlases (shown and re-mapped), 32-bit depth.
    estimate.items.push_back(
        {"vpls, shadow_res",
         absl::StrCat("two atlases of ", vpls, " VPL shadow maps of ", res, "^2"), 0,
         2 * vpls * res * res * 4});
    // Each atlas draws its proxy cuts through a batch of distance cubes.
    estimate.items.push_back(
        {"shadow_res", absl::StrCat("two batches of VPL distance cubes of ", res, "^2 faces"), 0,
         2 * avg::VplShadowMaps::CubeBatchBytes(int(res), int(vpls))});
    // Their draw lists: a view per VPL of a batch, a record per face.
    const uint64_t lists =
        2 *
        DrawList::MaxBytes(gpu, uint64_t(avg::VplShadowMaps::CubeBatch(int(res), int(vpls))), 6);
    estimate.items.push_back(
        {"vpls", "draw lists of two batches of VPL distance cubes", lists, lists});
  }
  // The approximate visibility grid: one 32-bit cell per voxel, on the CPU
  // for the VPL tracer and on the GPU.
  estimate.items.push_back({"grid", absl::StrCat("visibility grid of ", grid, "^3 voxels"),
                            grid * grid * grid * 4, grid * grid * grid * 4});
  estimate.items.push_back({"vpls", absl::StrCat(vpls, " VPLs"), vpls * 64, vpls * 64});
  estimate.items.push_back(
      DirectLightingMemory(params, state, gpu, "area_samples", "direct_shadow_res"));
  return estimate;
}

}  // namespace gistream
