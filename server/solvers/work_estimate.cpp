#include "solvers/work_estimate.h"

#include <absl/strings/str_cat.h>
#include <absl/strings/str_format.h>

#include <algorithm>

#include "render/area_lights.h"
#include "solvers/memory_estimate.h"

namespace gistream {

double WorkEstimate::seconds() const {
  double sum = 0.0;
  for (const WorkItem& item : items) sum += item.seconds;
  return sum;
}

const WorkItem* WorkEstimate::largest() const {
  const WorkItem* best = nullptr;
  for (const WorkItem& item : items) {
    if (best == nullptr || item.seconds > best->seconds) best = &item;
  }
  return best;
}

std::string WorkEstimate::Describe(const std::string& solver, const ParamSet& params) const {
  std::string out = absl::StrCat(solver, ":");
  const WorkItem* item = largest();
  if (item == nullptr) return absl::StrFormat("%s %.3g s", out, seconds());
  absl::StrAppend(&out, NamedParams(item->params, params),
                  absl::StrFormat(" (largest part: %s, %.3g s)", item->what, item->seconds));
  return out;
}

WorkItem Work(std::string params, std::string what, double ops, double ns_per_op) {
  return {std::move(params), std::move(what), ops, ops * ns_per_op * 1e-9};
}

double PassTriangles(const GpuScene& gpu) {
  double triangles = 0.0;
  for (const DrawItem& item : gpu.draws()) {
    const double full = item.index_count / 3.0;
    const int coarsest = item.first_level + item.level_count - 1;
    if (item.level_count <= 0 || coarsest < 0 || size_t(coarsest) >= gpu.levels().size()) {
      triangles += full;
      continue;
    }
    const double coarse = gpu.levels()[size_t(coarsest)].index_count / 3.0;
    triangles += coarse + 0.1 * std::max(0.0, full - coarse);
  }
  return triangles;
}

WorkItem DirectLightingWork(const ParamSet& params, const SceneState& state, const GpuScene& gpu,
                            const std::string& area_samples_param,
                            const std::string& shadow_res_param) {
  double cubes = 0, directional = 0;
  for (const LightInstance& l : state.lights()) {
    (l.light.type == LightType::kDirectional ? directional : cubes) += 1;
  }
  if (!CollectEmitters(state).empty()) cubes += std::max(0, params.GetInt(area_samples_param));
  const double res = std::max(0, params.GetInt(shadow_res_param));
  const double faces = 6 * cubes + directional;
  const double triangles = PassTriangles(gpu);
  const double texel_ns = faces * res * res * kShadowTexelNs;
  const double draw_ns = faces * triangles * kTriangleDrawNs;
  return Work(absl::StrCat(area_samples_param, ", ", shadow_res_param),
              absl::StrCat("direct light's shadow maps: ", faces, " faces of ", res, "^2 drawing ",
                           triangles, " triangles"),
              faces, (texel_ns + draw_ns) / std::max(faces, 1.0));
}

}  // namespace gistream
