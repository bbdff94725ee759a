#include "scene/proxy_levels.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>

#include "scene/proxy_clusters.h"
#include "scene/surface_distance.h"

namespace gistream {

std::vector<ProxyLevel> BuildProxyLevels(const Primitive& primitive,
                                         const ProxySettings& settings) {
  const size_t triangles = primitive.indices.size() / 3;
  if (triangles < settings.min_triangles || !primitive.joints.empty() ||
      !primitive.targets.empty() || primitive.bounds.empty()) {
    return {};
  }
  const float diagonal = glm::length(primitive.bounds.extent());
  if (!(diagonal > 0.0f) || !std::isfinite(diagonal)) return {};
  const std::vector<glm::vec3>& positions = primitive.positions;
  const float* xyz = &positions[0].x;
  // meshoptimizer's errors are relative to this scale.
  const float scale = meshopt_simplifyScale(xyz, positions.size(), sizeof(glm::vec3));
  const float cap = settings.max_relative_error * diagonal;
  const TriangleGrid full(positions, primitive.indices, cap / 4.0f);

  std::vector<ProxyLevel> levels;
  const std::vector<uint32_t>* finer = &primitive.indices;
  while (true) {
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
    const float there = HausdorffBound(positions, level.indices, full, spacing, cap);
    if (there >= cap) break;
    const float back = HausdorffBound(positions, primitive.indices, proxy, spacing, cap);
    if (back >= cap) break;
    level.error = std::max(there, back);
    levels.push_back(std::move(level));
    finer = &levels.back().indices;
  }
  return levels;
}

void BuildSceneProxies(Scene* scene, const ProxySettings& settings) {
  for (Mesh& mesh : scene->meshes) {
    for (Primitive& p : mesh.primitives) {
      p.proxies = BuildProxyLevels(p, settings);
      if (!p.proxies.empty()) p.clusters = BuildProxyClusters(p);
    }
  }
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
