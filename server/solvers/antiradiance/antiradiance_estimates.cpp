// AntiradianceSolver::EstimateMemory and EstimateWork
// (solvers/memory_estimate.h, solvers/work_estimate.h).
#include <algorithm>
#include <vector>

#include "solvers/antiradiance/antiradiance_solver.h"
#include "solvers/antiradiance/near_field.h"
#include "solvers/antiradiance/scene_patches.h"
#include "solvers/hierarchy/subdivide.h"

namespace gistream {
namespace {

struct Leaves {
  uint64_t count = 0;
  std::string driver;  // the parameters the count depends on, with bins
};

Leaves CountLeaves(const ParamSet& params, const SceneState& state, const GpuScene& gpu) {
  uint64_t leaves = 0;
  std::string driver;
  if (params.GetString("elements") == "surfels") {
    // The shared hierarchy's vertex discs: one leaf per instanced vertex
    // after long edges are split (hierarchy/subdivide.h), twice on a
    // doubleSided material (its back faces, antiradiance/patches.h).
    leaves = hierarchy::SubdividedVertexBound(state, gpu, params.GetBool("full_detail"),
                                              /*double_sided_twice=*/true) +
             // Refined near double-sided emitters (antiradiance/near_field.h).
             antiradiance::NearFieldVertexBound(state, gpu, params.GetBool("full_detail"));
    driver = "bins";
  } else {
    // Counted, not split: a tiny patch_size makes up to 4^12 leaves per
    // triangle (antiradiance::CountLeaves).
    const Bounds bounds = gpu.WorldBounds(state);
    const float diagonal = bounds.empty() ? 1.0f : glm::length(bounds.extent());
    const float patch_size = float(params.GetFloat("patch_size"));
    const float max_edge = patch_size > 0.0f ? patch_size : diagonal / 24.0f;
    auto groups = antiradiance::SceneTriangles(state);
    leaves = antiradiance::CountLeaves(groups, max_edge);
    // Back faces of doubleSided materials (antiradiance/patches.h).
    std::erase_if(groups, [&state](const std::vector<antiradiance::SourceTriangle>& g) {
      const int m = g.empty() ? -1 : g.front().tag;
      return m < 0 || size_t(m) >= state.materials().size() ||
             !state.materials()[size_t(m)].double_sided;
    });
    leaves += antiradiance::CountLeaves(groups, max_edge);
    driver = "patch_size, bins";
  }
  return {leaves, driver};
}

}  // namespace

MemoryEstimate AntiradianceSolver::EstimateMemory(const ParamSet& params, const SceneState& state,
                                                  const GpuScene& gpu) {
  const uint64_t bins = uint64_t(std::max(0, params.GetInt("bins")));
  MemoryEstimate estimate;
  const auto [leaves, driver] = CountLeaves(params, state, gpu);
  // A binary tree over the leaves: about as many clusters as leaves.
  const uint64_t nodes = 2 * leaves;
  // I_ex and L_in: nodes x bins x 2 x RGB floats (Section 3.1), plus the
  // per-node geometry (Patches: ~80 bytes) and each leaf's cell (a
  // vertex's third of up to ~6 triangles, 48-byte quads; links.cpp's exact
  // near form factors).
  estimate.items.push_back(
      {driver, absl::StrCat("I_ex/L_in tables of ", leaves, " leaves x ", bins, " bins"),
       nodes * bins * 2 * 12 + nodes * 80 + leaves * 6 * 48, 0});
  // Links: the oracle (Section 3.2) refines a receiver's links until each
  // sender covers at most one bin's solid angle, so a receiver that sees
  // the whole hemisphere keeps about one link per bin over its levels:
  // measured 0.99 x nodes x bins on the Cornell box (triangles,
  // patch_size 0.02, 512 bins: 30.2M links of 59,776 nodes). Kept per
  // pair of roots and once more sorted for the transport. (This was
  // 16 links per node, 30 times low there; issue 30.)
  estimate.items.push_back({driver, absl::StrCat("links of ", nodes, " elements x ", bins, " bins"),
                            2 * nodes * std::max<uint64_t>(bins, 1) * sizeof(antiradiance::Link),
                            0});
  // Display splats and their grid on the GPU (48 + 4 bytes per leaf).
  estimate.items.push_back({driver, "display elements", 0, leaves * 52});
  estimate.items.push_back(DirectLightingMemory(params, state, gpu, "area_samples", "shadow_res",
                                                /*environment_lights=*/true));
  return estimate;
}

WorkEstimate AntiradianceSolver::EstimateWork(const ParamSet& params, const SceneState& state,
                                              const GpuScene& gpu) {
  const double bins = std::max(1, params.GetInt("bins"));
  const auto [leaves, driver] = CountLeaves(params, state, gpu);
  // Nodes and links as in EstimateMemory: about one link per node and bin.
  const double updates = 2.0 * double(leaves) * bins;
  WorkEstimate estimate;
  // The Section 3.2 oracle tests about three node pairs per link it keeps:
  // the box's link stage, 340 ms for 5,544 nodes x 128 bins.
  estimate.items.push_back(
      Work(driver, absl::StrCat("linking: ", updates, " node-bin pairs"), updates, 480.0));
  // Every global pass (Eqs. 13-14) moves each link's bin and spreads, pushes
  // and pulls every node's bins: 815 ms for 32 passes on the box (the first
  // ones cost most; 40 ns an update on average). The asymmetric
  // scheme runs up to antiradiance_steps passes of Eq. 14 before each
  // radiance step.
  const double iterations = std::max(1, params.GetInt("iterations"));
  const bool asymmetric = params.GetString("scheme") == "asymmetric";
  const double passes = asymmetric
                            ? iterations * (std::max(1, params.GetInt("antiradiance_steps")) + 1.0)
                            : iterations;
  estimate.items.push_back(
      Work(absl::StrCat(driver,
                        asymmetric ? ", scheme, iterations, antiradiance_steps" : ", iterations"),
           absl::StrCat("global passes: ", passes, " x ", updates, " bin updates"),
           passes * updates, 40.0));
  estimate.items.push_back(DirectLightingWork(params, state, gpu));
  return estimate;
}

}  // namespace gistream
