#include "support/test_meshes.h"

#include <cmath>

#include "scene/proxies/proxy_levels.h"

namespace gistream::testing {
namespace {

// Two triangles per quad of a (columns + 1)-wide vertex lattice.
void AddLatticeQuads(Primitive& p, int rows, int columns) {
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const uint32_t a = uint32_t(r * (columns + 1) + c), b = a + 1, d0 = a + uint32_t(columns) + 1,
                     d1 = d0 + 1;
      p.indices.insert(p.indices.end(), {a, d0, d1, a, d1, b});
    }
  }
}

}  // namespace

Primitive FloorGrid(int n, float half) {
  Primitive floor;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const glm::vec3 v(half * (-1.0f + 2.0f * float(i) / float(n)), 0.0f,
                        half * (-1.0f + 2.0f * float(j) / float(n)));
      floor.positions.push_back(v);
      floor.normals.push_back({0, 1, 0});
      floor.bounds.Extend(v);
    }
  }
  AddLatticeQuads(floor, n, n);
  return floor;
}

Primitive UvSphere(const glm::vec3& center, float radius, int rings, int segments) {
  Primitive sphere;
  for (int r = 0; r <= rings; ++r) {
    const float theta = float(M_PI) * float(r) / float(rings);
    for (int s = 0; s <= segments; ++s) {
      const float phi = 2.0f * float(M_PI) * float(s) / float(segments);
      const glm::vec3 unit(std::sin(theta) * std::cos(phi), std::cos(theta),
                           std::sin(theta) * std::sin(phi));
      const glm::vec3 v = center + radius * unit;
      sphere.positions.push_back(v);
      sphere.normals.push_back(unit);
      sphere.bounds.Extend(v);
    }
  }
  AddLatticeQuads(sphere, rings, segments);
  return sphere;
}

std::shared_ptr<const Scene> FloorAndSphereScene(int floor_quads, int rings, int segments,
                                                 bool with_proxies) {
  Scene scene;
  scene.meshes.push_back({"floor", {FloorGrid(floor_quads)}});
  scene.meshes.push_back({"sphere", {UvSphere({0.0f, 0.5f, 0.0f}, 0.3f, rings, segments)}});
  for (int m = 0; m < 2; ++m) {
    Node node;
    node.mesh = m;
    scene.nodes.push_back(node);
    scene.roots.push_back(m);
    scene.bounds.Extend(scene.meshes[size_t(m)].primitives[0].bounds);
  }
  if (with_proxies) BuildSceneProxies(&scene);
  return std::make_shared<const Scene>(std::move(scene));
}

}  // namespace gistream::testing
