#include "scene/scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include "util/status.h"

namespace gistream {

Bounds Bounds::Transformed(const glm::mat4& m) const {
  Bounds world;
  if (empty()) return world;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? max.x : min.x, (corner & 2) ? max.y : min.y,
                      (corner & 4) ? max.z : min.z);
    world.Extend(glm::vec3(m * glm::vec4(p, 1.0f)));
  }
  return world;
}

std::vector<int> LightInstanceNodes(const Scene& scene) {
  std::vector<int> out;
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].light >= 0) out.push_back(static_cast<int>(i));
  }
  return out;
}

std::vector<int> CameraInstanceNodes(const Scene& scene) {
  std::vector<int> out;
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].camera >= 0) out.push_back(static_cast<int>(i));
  }
  return out;
}

glm::mat4 LocalMatrix(const Node& node) {
  const glm::mat4 t = glm::translate(glm::mat4(1.0f), node.translation);
  const glm::mat4 r = glm::mat4_cast(node.rotation);
  const glm::mat4 s = glm::scale(glm::mat4(1.0f), node.scale);
  return t * r * s;
}

std::vector<glm::mat4> WorldMatrices(const Scene& scene, const std::vector<Node>& nodes) {
  // `nodes` is a (possibly edited) copy of the scene's nodes; the hierarchy
  // must be the scene's.
  GS_CHECK(nodes.size() == scene.nodes.size());
  std::vector<glm::mat4> world(nodes.size());
  std::vector<bool> done(nodes.size(), false);
  std::vector<size_t> chain;
  for (size_t i = 0; i < nodes.size(); ++i) {
    // Walk up to the first ancestor already done, then come back down.
    chain.clear();
    for (int n = static_cast<int>(i); n >= 0 && !done[size_t(n)]; n = nodes[size_t(n)].parent) {
      GS_CHECK(static_cast<size_t>(n) < nodes.size());
      chain.push_back(size_t(n));
      GS_CHECK(chain.size() <= nodes.size());  // a cycle: import forbids them
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const Node& node = nodes[*it];
      const glm::mat4 local = LocalMatrix(node);
      world[*it] = node.parent >= 0 ? world[size_t(node.parent)] * local : local;
      done[*it] = true;
    }
  }
  return world;
}

}  // namespace gistream
