// AvgSolver::EstimateMemory and EstimateWork (solvers/memory_estimate.h,
// solvers/work_estimate.h).
#include <algorithm>

#include "solvers/avg/avg_solver.h"
#include "solvers/avg/vpl_shadow_maps.h"
#include "scene/gpu/draw_list.h"

namespace gistream {

MemoryEstimate AvgSolver::EstimateMemory(const ParamSet& params, const SceneState& state,
                                         const GpuScene& gpu) {
  // A still view's VPLs (`still_vpls`) when more: the atlases hold them.
  const uint64_t vpls = uint64_t(std::max({0, params.GetInt("vpls"), params.GetInt("still_vpls")}));
  const uint64_t res = uint64_t(std::max(0, params.GetInt("shadow_res")));
  const uint64_t grid = uint64_t(std::max(0, params.GetInt("grid")));
  MemoryEstimate estimate;
  if (params.GetBool("visibility")) {
    // Two paraboloid atlases (shown and re-mapped), 32-bit depth.
    estimate.items.push_back(
        {"vpls, still_vpls, shadow_res",
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
  // The approximate visibility grid: on the CPU each voxel's sums
  // (avg::Voxel: normal, albedo, BRDF, point, counts) for the VPL tracer,
  // on the GPU one 32-bit cell per voxel.
  estimate.items.push_back({"grid", absl::StrCat("visibility grid of ", grid, "^3 voxels"),
                            grid * grid * grid * sizeof(avg::Voxel), grid * grid * grid * 4});
  // A VPL: about 100 bytes on the CPU (avg::Vpl), 96 on the GPU (GpuVpl).
  estimate.items.push_back({"vpls", absl::StrCat(vpls, " VPLs"), vpls * 100, vpls * 96});
  estimate.items.push_back(DirectLightingMemory(params, state, gpu, "area_samples",
                                                "direct_shadow_res", /*environment_lights=*/true));
  return estimate;
}

WorkEstimate AvgSolver::EstimateWork(const ParamSet& params, const SceneState& state,
                                     const GpuScene& gpu) {
  // A complete solve includes a still view's VPLs (`still_vpls`): its
  // second set is traced and mapped after the first.
  const double vpls = std::max({0, params.GetInt("vpls"), params.GetInt("still_vpls")});
  const double res = std::max(0, params.GetInt("shadow_res"));
  const double grid = std::max(0, params.GetInt("grid"));
  const double triangles = PassTriangles(gpu);
  WorkEstimate estimate;
  // Voxelize: every voxel of the grid (Section 3.1; 28 ms for 64^3 on the
  // box) and every triangle once.
  estimate.items.push_back(Work("grid", absl::StrCat("voxelize: ", grid, "^3 voxels"),
                                grid * grid * grid + triangles, 110.0));
  // Trace: each VPL ends a path segment that marches up to 3 x grid voxels
  // (Section 3.2; 1.5 ms for 680 VPLs on the box).
  const double steps = vpls * 3.0 * grid;
  estimate.items.push_back(
      Work("vpls, still_vpls, grid", absl::StrCat("trace: ", steps, " voxel steps"), steps, 35.0));
  if (params.GetBool("visibility")) {
    // A distance cube per VPL (6 faces of shadow_res^2, each a draw of the
    // scene), per face 157 us at 64^2 and 740 us at 256^2 on the box: 10 ns
    // a texel and 110 us for the face's draw. Counted for all `vpls`; a
    // path ends early where light escapes (680 of 1,024 on the box).
    const double faces = 6.0 * vpls;
    estimate.items.push_back(Work("vpls, still_vpls, shadow_res",
                                  absl::StrCat("VPL shadow maps: ", faces, " faces of ", res,
                                               "^2 drawing ", triangles, " triangles"),
                                  faces,
                                  res * res * 10.0 + triangles * kTriangleDrawNs + 110'000.0));
  }
  estimate.items.push_back(
      DirectLightingWork(params, state, gpu, "area_samples", "direct_shadow_res"));
  return estimate;
}

}  // namespace gistream
