// hierarchy::TransferVertices (issue 19): a full mesh's vertices onto the
// nearest triangle of its proxy, and the proxy level as an element mesh
// (hierarchy::ProxyLevelMesh).
#include <gtest/gtest.h>

#include "scene/proxies/proxy_levels.h"
#include "solvers/hierarchy/element_source.h"
#include "solvers/hierarchy/vertex_transfer.h"
#include "support/test_meshes.h"

namespace gistream {
namespace vertex_transfer_test {

TEST(VertexTransfer, FullMeshVerticesLandOnTheProxyWithinItsError) {
  // A UV sphere (radius 0.3, 48 x 96 quads) and its coarsest level: every
  // vertex's weights are barycentrics (>= 0, sum 1) and the point they give
  // on the proxy is within the level's recorded error of the vertex (the
  // error bounds the distance both ways), on the side the vertex faces.
  Primitive sphere = testing::UvSphere({0.0f, 0.0f, 0.0f}, 0.3f, 48, 96);
  sphere.proxies = BuildProxyLevels(sphere);
  ASSERT_FALSE(sphere.proxies.empty());
  const int level = int(sphere.proxies.size()) - 1;
  const Primitive proxy = hierarchy::ProxyLevelMesh(sphere, level);
  ASSERT_EQ(proxy.indices.size(), sphere.proxies[size_t(level)].indices.size());
  ASSERT_LT(proxy.positions.size(), sphere.positions.size());
  const float error = sphere.proxies[size_t(level)].error;
  const hierarchy::VertexTransfer t = hierarchy::TransferVertices(sphere, proxy);
  ASSERT_EQ(t.corner.size(), sphere.positions.size());
  float worst = 0.0f;
  for (size_t v = 0; v < sphere.positions.size(); ++v) {
    const glm::vec3 w = t.weight[v];
    EXPECT_GE(std::min({w.x, w.y, w.z}), 0.0f);
    EXPECT_NEAR(w.x + w.y + w.z, 1.0f, 1e-5f);
    glm::vec3 q(0.0f), n(0.0f);
    for (int k = 0; k < 3; ++k) {
      ASSERT_LT(t.corner[v][k], proxy.positions.size());
      q += w[k] * proxy.positions[t.corner[v][k]];
      n += w[k] * proxy.normals[t.corner[v][k]];
    }
    worst = std::max(worst, glm::length(q - sphere.positions[v]));
    EXPECT_GT(glm::dot(n, sphere.normals[v]), 0.0f);
  }
  EXPECT_LE(worst, error * (1.0f + 1e-4f));
}

TEST(VertexTransfer, ElementLevelIsTheCoarsestWithinATenthOfTheElementSize) {
  Primitive sphere = testing::UvSphere({0.0f, 0.0f, 0.0f}, 0.3f, 48, 96);
  sphere.proxies = BuildProxyLevels(sphere);
  ASSERT_GE(sphere.proxies.size(), 2u);
  const float e0 = sphere.proxies[0].error;
  // The limit whose tenth is the finest level's error: that level at least.
  const float max_edge = e0 / hierarchy::kProxyErrorFraction;
  const int level = hierarchy::ElementLevel(sphere, max_edge, false);
  ASSERT_GE(level, 0);
  EXPECT_LE(sphere.proxies[size_t(level)].error, e0);
  if (size_t(level) + 1 < sphere.proxies.size()) {
    EXPECT_GT(sphere.proxies[size_t(level) + 1].error, e0);
  }
  EXPECT_EQ(hierarchy::ElementLevel(sphere, max_edge, true), -1);          // full_detail
  EXPECT_EQ(hierarchy::ElementLevel(sphere, 0.5f * max_edge, false), -1);  // too fine for any level
  EXPECT_EQ(hierarchy::ElementLevel(sphere, 0.0f, false), -1);
  Primitive small = testing::FloorGrid(40);  // 3,200 triangles, flat
  small.proxies = BuildProxyLevels(small);
  ASSERT_FALSE(small.proxies.empty());
  EXPECT_EQ(hierarchy::ElementLevel(small, 1.0f, false), -1);  // below kMinProxyTriangles
}

}  // namespace vertex_transfer_test
}  // namespace gistream
