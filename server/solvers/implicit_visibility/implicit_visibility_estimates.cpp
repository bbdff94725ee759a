// ImplicitVisibilitySolver::EstimateMemory and EstimateWork
// (solvers/memory_estimate.h, solvers/work_estimate.h).
#include <algorithm>

#include "solvers/hierarchy/subdivide.h"
#include "solvers/implicit_visibility/implicit_visibility_solver.h"

namespace gistream {
namespace {

// Whether any material can make a leaf glossy (illumination.h: roughness
// below 0.9; a texture may lower it).
bool HasGlossyMaterial(const SceneState& state) {
  for (const Material& m : state.materials()) {
    if (m.roughness_factor < 0.9f || m.metallic_roughness_texture >= 0) return true;
  }
  return false;
}

}  // namespace

MemoryEstimate ImplicitVisibilitySolver::EstimateMemory(const ParamSet& params,
                                                        const SceneState& state,
                                                        const GpuScene& gpu) {
  const uint64_t n = uint64_t(std::max(0, params.GetInt("bins_per_face")));
  const uint64_t bins = 6 * n * n;
  // The shared hierarchy: one leaf disc per instanced vertex after long
  // edges are split (hierarchy/subdivide.h), a binary tree of clusters
  // above them.
  const uint64_t nodes =
      2 * hierarchy::SubdividedVertexBound(state, gpu, params.GetBool("full_detail"));
  MemoryEstimate estimate;
  // Bin tables: nodes x 6 N^2 RGB floats (CheckBinBytes), on the CPU for
  // the background relink and on the GPU for the gather.
  estimate.items.push_back({"bins_per_face",
                            absl::StrCat("cube-map bins of ", nodes, " elements x ", bins, " bins"),
                            nodes * bins * 12, nodes * bins * 12});
  // Links (~16 per element, 16 bytes each) and the element buffers.
  estimate.items.push_back({"", absl::StrCat("links and elements of ", nodes, " elements"),
                            nodes * (16 * 16 + 96), nodes * (16 * 16 + 96)});
  // Glossy elements' directional bins (illumination.h): at most every
  // element a slot, and no more leaves than kMaxGlossyWork / bins (twice
  // as many slots with the nodes above them).
  if (params.GetBool("glossy") && HasGlossyMaterial(state)) {
    const int glossy_bins = std::max(1, params.GetInt("glossy_bins"));
    const uint64_t slots =
        std::min<uint64_t>(nodes, 2 * uint64_t(Illumination::kMaxGlossyWork / double(glossy_bins)));
    const uint64_t bytes = slots * Illumination::GlossySlotBytes(glossy_bins);
    estimate.items.push_back({"glossy_bins",
                              absl::StrCat("directional bins of up to ", slots, " glossy elements"),
                              0, bytes});
  }
  estimate.items.push_back(DirectLightingMemory(params, state, gpu));
  return estimate;
}

WorkEstimate ImplicitVisibilitySolver::EstimateWork(const ParamSet& params, const SceneState& state,
                                                    const GpuScene& gpu) {
  const double n = std::max(1, params.GetInt("bins_per_face"));
  const double bins = 6 * n * n;
  const double nodes =
      2.0 * double(hierarchy::SubdividedVertexBound(state, gpu, params.GetBool("full_detail")));
  const double pairs = nodes * bins;
  // Nested surfaces are offered to each bin one behind another: linking
  // grows with the depth complexity past the box's 2.1 (work_estimate.h;
  // 2CylinderEngine, depth 5.2: 172 s for 1.8e8 pairs, 2.9x the box's
  // rate per pair).
  const double depth = DepthComplexity(state, gpu);
  WorkEstimate estimate;
  // create_links: each element's cube of bins is offered about one node
  // pair per bin (node_pairs 4.36M for 5,544 nodes x 864 bins on the
  // box, 1,586 ms; Section 4's link creation).
  estimate.items.push_back(
      Work("bins_per_face",
           absl::StrCat("linking: ", pairs, " element-bin pairs at depth ", absl::SixDigits(depth)),
           pairs * std::max(1.0, depth / 2.0), 330.0));
  // Every bounce gathers each element's bins and pushes/pulls the
  // hierarchy (illumination + refine_push: 344 ms for 32 bounces on the
  // box); up to `bounces`.
  const double bounces = std::max(1, params.GetInt("bounces"));
  estimate.items.push_back(Work("bins_per_face, bounces",
                                absl::StrCat("bounces: ", bounces, " x ", pairs, " bin gathers"),
                                bounces * pairs, 2.25));
  estimate.items.push_back(DirectLightingWork(params, state, gpu));
  return estimate;
}

}  // namespace gistream
