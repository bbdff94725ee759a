#include "solvers/work_estimate.h"

#include <absl/strings/str_cat.h>
#include <absl/strings/str_format.h>

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

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

double DepthComplexity(const SceneState& state, const GpuScene& gpu) {
  const Bounds bounds = gpu.WorldBounds(state);
  if (bounds.empty()) return 1.0;
  const glm::dvec3 d = glm::dvec3(bounds.max) - glm::dvec3(bounds.min);
  const double surface = 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
  const Scene& scene = state.scene();
  double area = 0.0;
  for (const DrawItem& item : gpu.draws()) {
    if (item.mesh < 0 || size_t(item.mesh) >= scene.meshes.size() || item.node < 0 ||
        size_t(item.node) >= state.world().size())
      continue;
    const Mesh& mesh = scene.meshes[size_t(item.mesh)];
    if (item.primitive < 0 || size_t(item.primitive) >= mesh.primitives.size()) continue;
    const Primitive& p = mesh.primitives[size_t(item.primitive)];
    const glm::dmat4 m(state.world()[size_t(item.node)]);
    for (size_t t = 0; t + 2 < p.indices.size(); t += 3) {
      const uint32_t i0 = p.indices[t], i1 = p.indices[t + 1], i2 = p.indices[t + 2];
      if (i0 >= p.positions.size() || i1 >= p.positions.size() || i2 >= p.positions.size())
        continue;
      const glm::dvec3 a(m * glm::dvec4(glm::dvec3(p.positions[i0]), 1.0));
      const glm::dvec3 b(m * glm::dvec4(glm::dvec3(p.positions[i1]), 1.0));
      const glm::dvec3 c(m * glm::dvec4(glm::dvec3(p.positions[i2]), 1.0));
      area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
  }
  const double ratio = 2.0 * area / surface;
  return std::isfinite(ratio) ? std::max(1.0, ratio) : 1.0;
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
