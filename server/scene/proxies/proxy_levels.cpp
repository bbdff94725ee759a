#include "scene/proxies/proxy_levels.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>

#include "scene/proxies/proxy_clusters.h"
#include "scene/proxies/surface_distance.h"

namespace gistream {

namespace {

bool MayHaveLevels(const Primitive& primitive, const ProxySettings& settings) {
  const float diagonal = glm::length(primitive.bounds.extent());
  return primitive.indices.size() / 3 >= settings.min_triangles && primitive.joints.empty() &&
         primitive.targets.empty() && !primitive.bounds.empty() && diagonal > 0.0f &&
         std::isfinite(diagonal);
}

}  // namespace

std::vector<ProxyLevel> BuildProxyLevels(const Primitive& primitive,
                                         const ProxySettings& settings) {
  bool out_of_time = false;
  absl::StatusOr<std::vector<ProxyLevel>> levels =
      BuildProxyLevels(primitive, settings, LoadControl{}, &out_of_time);
  return levels.ok() ? *std::move(levels) : std::vector<ProxyLevel>{};
}

absl::StatusOr<std::vector<ProxyLevel>> BuildProxyLevels(const Primitive& primitive,
                                                         const ProxySettings& settings,
                                                         const LoadControl& control,
                                                         bool* out_of_time) {
  *out_of_time = false;
  if (!MayHaveLevels(primitive, settings)) return std::vector<ProxyLevel>{};
  const float diagonal = glm::length(primitive.bounds.extent());
  const std::vector<glm::vec3>& positions = primitive.positions;
  const float* xyz = &positions[0].x;
  // meshoptimizer's errors are relative to this scale.
  const float scale = meshopt_simplifyScale(xyz, positions.size(), sizeof(glm::vec3));
  const float cap = settings.max_relative_error * diagonal;
  const TriangleGrid full(positions, primitive.indices, cap / 4.0f);

  std::vector<ProxyLevel> levels;
  const std::vector<uint32_t>* finer = &primitive.indices;
  while (true) {
    GS_RETURN_IF_ERROR(control.Check("proxy levels"));
    if (!control.OptionalTimeLeft()) {
      *out_of_time = true;
      break;
    }
    const size_t finer_count = finer->size();
    const size_t target =
        std::max<size_t>(3, size_t(float(finer_count / 3) * settings.reduction) * 3);
    ProxyLevel level;
    level.indices.resize(finer_count);
    float relative_error = 0.0f;
    // Each level simplifies the one before (cheaper); its error is
    // measured against the full mesh all the same.
    level.indices.resize(meshopt_simplify(level.indices.data(), finer->data(), finer_count, xyz,
                                          positions.size(), sizeof(glm::vec3), target,
                                          cap / std::max(scale, 1e-30f), 0, &relative_error));
    if (level.indices.empty() || level.indices.size() * 2 > finer_count) break;
    // The measured bound, both ways: proxy -> full and full -> proxy. The
    // spacing follows meshoptimizer's own estimate so that the covering
    // radius stays a fraction of the error.
    const float spacing =
        std::max(0.5f * relative_error * scale, settings.min_relative_spacing * diagonal);
    const TriangleGrid proxy(positions, level.indices, cap / 4.0f);
    const float there =
        HausdorffBound(positions, level.indices, full, spacing, cap, control.optional_deadline);
    if (there >= cap) break;
    const float back = HausdorffBound(positions, primitive.indices, proxy, spacing, cap,
                                      control.optional_deadline);
    if (back >= cap) break;
    level.error = std::max(there, back);
    levels.push_back(std::move(level));
    finer = &levels.back().indices;
  }
  // A measurement the deadline cut short answers `cap`, as a rejected level.
  if (!control.OptionalTimeLeft()) *out_of_time = true;
  return levels;
}

void BuildSceneProxies(Scene* scene, const ProxySettings& settings) {
  ProxyReport report;
  (void)BuildSceneProxies(scene, LoadControl{}, &report, settings);
}

absl::Status BuildSceneProxies(Scene* scene, const LoadControl& control, ProxyReport* report,
                               const ProxySettings& settings) {
  const auto start = LoadControl::Clock::now();
  *report = {};
  const auto named = [](size_t m, size_t i, const absl::Status& status) {
    return absl::Status(status.code(),
                        absl::StrCat("meshes[", m, "].primitives[", i, "]: ", status.message()));
  };
  // The levels of every primitive first: they are cheap and most of the
  // gain; then the trees, which a passed deadline drops.
  std::vector<std::vector<bool>> levels_cut(scene->meshes.size());
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t m = 0; m < scene->meshes.size(); ++m) {
      std::vector<Primitive>& primitives = scene->meshes[m].primitives;
      levels_cut[m].resize(primitives.size(), false);
      for (size_t i = 0; i < primitives.size(); ++i) {
        Primitive& p = primitives[i];
        bool out_of_time = false;
        if (pass == 0) {
          if (!MayHaveLevels(p, settings)) continue;
          absl::StatusOr<std::vector<ProxyLevel>> levels =
              BuildProxyLevels(p, settings, control, &out_of_time);
          if (!levels.ok()) return named(m, i, levels.status());
          p.proxies = *std::move(levels);
          report->primitives_with_levels += p.proxies.empty() ? 0 : 1;
          report->levels_skipped += out_of_time ? 1 : 0;
          levels_cut[m][i] = out_of_time;
          continue;
        }
        if (p.proxies.empty()) {
          // Cut before its first level: a tree-sized primitive lacks both.
          const bool tree_sized = p.indices.size() / 3 > 2 * ClusterSettings{}.leaf_triangles;
          report->trees_skipped += levels_cut[m][i] && tree_sized ? 1 : 0;
          continue;
        }
        absl::StatusOr<std::vector<ProxyCluster>> tree =
            BuildProxyClusters(p, ClusterSettings{}, control, &out_of_time);
        if (!tree.ok()) return named(m, i, tree.status());
        p.clusters = *std::move(tree);
        report->primitives_with_trees += p.clusters.empty() ? 0 : 1;
        report->trees_skipped += out_of_time ? 1 : 0;
      }
    }
  }
  report->seconds = std::chrono::duration<double>(LoadControl::Clock::now() - start).count();
  return absl::OkStatus();
}

float MaxScale(const glm::mat4& model) {
  const glm::mat3 a(model);
  const glm::mat3 ata = glm::transpose(a) * a;
  float row = 0.0f;
  for (int r = 0; r < 3; ++r) {
    row = std::max(row, std::abs(ata[0][r]) + std::abs(ata[1][r]) + std::abs(ata[2][r]));
  }
  return std::sqrt(row);
}

}  // namespace gistream
