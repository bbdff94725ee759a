// What a complete solve costs, estimated from a solver's parameters and the
// scene before it is built (issue 30: cost before work). Every solver offers
//   static WorkEstimate EstimateWork(const ParamSet&, const SceneState&,
//                                    const GpuScene&);
// registered beside EstimateMemory (solvers/registry.h). The engine checks
// the total against --max-solve-seconds in one place before it builds the
// solver, and answers RESOURCE_EXHAUSTED naming the parameters of the
// largest item when it is over.
//
// An item counts its stage's work at the parameters' caps (every bounce or
// iteration up to `bounces` / `iterations`, as with `tolerance` 0: the
// stiff scene a tolerance never stops early), in the units that drive it
// (link pairs, bin updates, cube-map texels, triangles drawn), and turns
// them into seconds on the reference machine: 2 cores, Mesa llvmpipe, where
// the rates below were measured on the Cornell box from the stages' own
// timings (docs/RESULTS.md, "Solve-time estimates"). A GPU server is faster,
// so the limit is conservative there; --solve-speed says how much.
// Estimates are cheap (counting, never building).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"
#include "solvers/solver_params.h"

namespace gistream {

struct WorkItem {
  // The parameters that drive it, comma-separated ("bins, iterations").
  std::string params;
  std::string what;      // "global passes: 32 x 709632 bin updates"
  double ops = 0.0;      // in the item's own unit (see `what`)
  double seconds = 0.0;  // on the reference machine
};

struct WorkEstimate {
  std::vector<WorkItem> items;
  double seconds() const;
  const WorkItem* largest() const;  // nullptr when there are none
  // "antiradiance: bins=512 iterations=4096 (largest part: global passes:
  // ..., 2.1e+05 s)": names the parameters of the largest item and their
  // values, for the engine's RESOURCE_EXHAUSTED.
  std::string Describe(const std::string& solver, const ParamSet& params) const;
};

// One item of `ops` units at `ns_per_op` reference nanoseconds each.
WorkItem Work(std::string params, std::string what, double ops, double ns_per_op);

// Reference costs shared by several solvers (2-core llvmpipe, Cornell box).
// A depth texel of a shadow or distance cube map: implicit_visibility's
// shadow_maps stage, 432 ms for 64 samples x 6 faces x 256^2.
inline constexpr double kShadowTexelNs = 17.0;
// A triangle submitted to one cube face or map: sh_probes' per-face cost at
// face_size 4 (44 ms a bounce for 3,072 faces of the box's triangles).
inline constexpr double kTriangleDrawNs = 2.5;

// The triangles a view-independent pass (a cube face, a shadow map) draws
// of the whole scene: the full meshes where a primitive has no proxy
// levels; where it has, its coarsest level plus a tenth of the rest (the
// levels are chosen per draw by the error a pass tolerates there: on a
// 196,608-triangle box sh_probes' faces drew about 4 % of it).
double PassTriangles(const GpuScene& gpu);

// The scene's depth complexity: how many surfaces a line through its
// bounds crosses on average, by Cauchy-Crofton 2 A / S for the triangles'
// world-space area A (each side counted once) inside bounds of surface S;
// at least 1. A room is about 1.5, a machine of nested parts several
// times that: hierarchical linking offers each element a node per bin
// per surface behind surface, so its work grows with it. O(triangles).
double DepthComplexity(const SceneState& state, const GpuScene& gpu);

// Direct light's shadow maps (render/direct_lighting.h), drawn once per
// light change: one cube per point/spot light and area sample, one map per
// directional light, each face a draw of PassTriangles.
WorkItem DirectLightingWork(const ParamSet& params, const SceneState& state, const GpuScene& gpu,
                            const std::string& area_samples_param = "area_samples",
                            const std::string& shadow_res_param = "shadow_res");

}  // namespace gistream
