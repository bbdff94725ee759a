#include "solvers/memory_estimate.h"

#include <absl/strings/str_split.h>

#include <algorithm>

#include "render/area_lights.h"
#include "render/direct_lighting.h"
#include "scene/gpu/draw_list.h"
#include "util/memory_budget.h"

namespace gistream {

uint64_t MemoryEstimate::cpu_bytes() const {
  uint64_t sum = 0;
  for (const MemoryItem& item : items) sum += item.cpu_bytes;
  return sum;
}

uint64_t MemoryEstimate::gpu_bytes() const {
  uint64_t sum = 0;
  for (const MemoryItem& item : items) sum += item.gpu_bytes;
  return sum;
}

const MemoryItem* MemoryEstimate::largest() const {
  const MemoryItem* best = nullptr;
  for (const MemoryItem& item : items) {
    if (best == nullptr || item.bytes() > best->bytes()) best = &item;
  }
  return best;
}

std::string MemoryEstimate::Describe(const std::string& solver, const ParamSet& params) const {
  std::string out = absl::StrCat(solver, ":");
  const MemoryItem* item = largest();
  if (item == nullptr) return absl::StrCat(out, " ", FormatBytes(bytes()));
  absl::StrAppend(&out, NamedParams(item->params, params), " (largest part: ", item->what, ", ",
                  FormatBytes(item->bytes()), ")");
  return out;
}

std::string NamedParams(const std::string& names, const ParamSet& params) {
  std::string out;
  for (const std::string& name :
       std::vector<std::string>(absl::StrSplit(names, ", ", absl::SkipEmpty()))) {
    auto it = params.values().find(name);
    absl::StrAppend(&out, " ", name, "=", it != params.values().end() ? it->second : "?");
  }
  return out;
}

MemoryItem DirectLightingMemory(const ParamSet& params, const SceneState& state,
                                const GpuScene& gpu, const std::string& area_samples_param,
                                const std::string& shadow_res_param, bool environment_lights) {
  uint64_t cubes = 0, directional = 0;
  if (environment_lights && state.scene().environment) {
    directional += state.scene().environment->light_cut.size();
  }
  for (const LightInstance& l : state.lights()) {
    (l.light.type == LightType::kDirectional ? directional : cubes) += 1;
  }
  const uint64_t samples = uint64_t(std::max(0, params.GetInt(area_samples_param)));
  if (!CollectEmitters(state).empty()) cubes += samples;
  const uint64_t res = uint64_t(std::max(0, params.GetInt(shadow_res_param)));
  uint64_t bytes = res * res * 4 * (6 * cubes + directional);
  // The second set for a sliced redraw exists only when both fit the cap.
  if (2 * bytes <= DirectLighting::kMaxShadowBytes) bytes *= 2;
  const uint64_t lists = DrawList::MaxBytes(gpu, 2, 6);
  return {absl::StrCat(area_samples_param, ", ", shadow_res_param),
          absl::StrCat("direct light's shadow maps: ", 6 * cubes + directional, " faces of ", res,
                       "^2, and their draw lists"),
          lists, bytes + lists};
}

InstancedCounts CountInstanced(const SceneState& state) {
  InstancedCounts counts;
  const Scene& scene = state.scene();
  for (const Node& node : state.nodes()) {
    if (node.mesh < 0 || size_t(node.mesh) >= scene.meshes.size()) continue;
    for (const Primitive& p : scene.meshes[size_t(node.mesh)].primitives) {
      counts.vertices += p.positions.size();
      counts.triangles += p.indices.size() / 3;
    }
  }
  return counts;
}

}  // namespace gistream
