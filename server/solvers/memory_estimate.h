// What a solver will allocate, estimated from its parameters and the scene
// before it is built. Every solver offers
//   static MemoryEstimate EstimateMemory(const ParamSet&, const SceneState&,
//                                        const GpuScene&);
// registered beside Describe and Create (solvers/registry.h); the engine
// reserves the total from the server's memory budget (util/memory_budget.h)
// in one place before it calls Create, and answers RESOURCE_EXHAUSTED
// naming the parameters of the largest item when it does not fit.
//
// Estimates cover the dominant buffers (those that grow with a parameter
// or the scene), not programs or small uniform buffers. They must be cheap
// (counting, never building) and never below the real need of an item, so
// that a refusal is never wrong by much and an acceptance never is.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"
#include "solvers/solver_params.h"

namespace gistream {

struct MemoryItem {
  // The parameters that drive it, comma-separated ("patch_size, bins"); ""
  // for what only the scene drives.
  std::string params;
  std::string what;  // "I_ex/L_in tables: 1234567 leaves x 128 bins"
  uint64_t cpu_bytes = 0;
  uint64_t gpu_bytes = 0;
  uint64_t bytes() const { return cpu_bytes + gpu_bytes; }
};

struct MemoryEstimate {
  std::vector<MemoryItem> items;
  uint64_t cpu_bytes() const;
  uint64_t gpu_bytes() const;
  uint64_t bytes() const { return cpu_bytes() + gpu_bytes(); }
  // The item with the most bytes (nullptr when there are none).
  const MemoryItem* largest() const;
  // "antiradiance: patch_size=1e-06 bins=128 (largest part: I_ex/L_in
  // tables of ... leaves x 128 bins, 5.1 GiB)": names the parameters of the
  // largest item and their values, for MemoryBudget::Reserve's message.
  std::string Describe(const std::string& solver, const ParamSet& params) const;
};

// Shared parts of the estimates.
// " name=value" for each of the comma-separated `names` ("bins, iterations")
// with its value in `params` ("?" when it has none): what a refusal names.
std::string NamedParams(const std::string& names, const ParamSet& params);
// Direct light's shadow maps (render/direct_lighting.h): one cube per
// point/spot light and area sample, one map per directional light, at
// `shadow_res_param`^2, depth 32 bits, twice while a sliced redraw runs;
// and the draw lists they are drawn from (a cube's, and the one before it
// that the GL may still read). `environment_lights`: the solver's
// DirectLightingSettings::environment_lights (a map per light of the
// environment's cut).
MemoryItem DirectLightingMemory(const ParamSet& params, const SceneState& state,
                                const GpuScene& gpu,
                                const std::string& area_samples_param = "area_samples",
                                const std::string& shadow_res_param = "shadow_res",
                                bool environment_lights = false);
// Vertices and triangles over every mesh instance of the current state.
struct InstancedCounts {
  uint64_t vertices = 0;
  uint64_t triangles = 0;
};
InstancedCounts CountInstanced(const SceneState& state);

}  // namespace gistream
