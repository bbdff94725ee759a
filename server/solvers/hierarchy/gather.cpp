#include "solvers/hierarchy/gather.h"

#include "util/parallel_for.h"

namespace gistream::hierarchy {

std::vector<glm::vec3> Gather(const LeafLinks& links, const std::vector<glm::vec3>& radiance) {
  const size_t leaves = links.offset.empty() ? 0 : links.offset.size() - 1;
  std::vector<glm::vec3> e(leaves, glm::vec3(0.0f));
  ParallelFor(leaves, 64, [&](size_t i) {
    glm::vec3 sum(0.0f);
    for (uint32_t k = links.offset[i]; k < links.offset[i + 1]; ++k) {
      sum += links.weight[k] * radiance[links.source[k]];
    }
    e[i] = sum;
  });
  return e;
}

void PullUp(const Elements& elements, std::vector<glm::vec3>& radiance) {
  const std::vector<int>& levels = elements.level_begin();
  for (size_t h = 1; h < levels.size(); ++h) {
    for (int node = levels[h - 1]; node < levels[h]; ++node) {
      glm::vec3 sum(0.0f);
      float area = 0.0f;
      for (int c : elements.children[size_t(node)]) {
        if (c < 0) continue;
        sum += elements.area[size_t(c)] * radiance[size_t(c)];
        area += elements.area[size_t(c)];
      }
      radiance[size_t(node)] = area > 0.0f ? sum / area : glm::vec3(0.0f);
    }
  }
}

}  // namespace gistream::hierarchy
