// ImplicitVisibilitySolver::EstimateMemory (solvers/memory_estimate.h).
#include <algorithm>

#include "solvers/hierarchy/subdivide.h"
#include "solvers/implicit_visibility/implicit_visibility_solver.h"

namespace gistream {

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
  estimate.items.push_back(DirectLightingMemory(params, state, gpu));
  return estimate;
}

}  // namespace gistream
