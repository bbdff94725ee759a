// Proxy levels (issue 19): each simplified level's geometric error, measured
// here on the mesh by brute force, is within the bound import recorded.
#include "scene/proxies/proxy_levels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/proxies/proxy_clusters.h"
#include "scene/gpu/scene_memory.h"
#include "scene/proxies/surface_distance.h"
#include "support/test_meshes.h"

namespace gistream {
namespace proxy_levels_test {

// A UV sphere of radius 1 (rings x segments quads, poles included): curved
// everywhere, so every simplified level has a real error.
Primitive Sphere(int rings, int segments) {
  return testing::UvSphere(glm::vec3(0.0f), 1.0f, rings, segments);
}

// A height field over [0, 1]^2 with gentle bumps and a border.
Primitive BumpyPlane(int n) {
  Primitive p;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float x = float(i) / float(n), z = float(j) / float(n);
      const glm::vec3 v(x, 0.01f * std::sin(6.0f * x) * std::cos(5.0f * z), z);
      p.positions.push_back(v);
      p.normals.push_back({0, 1, 0});
      p.bounds.Extend(v);
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      p.indices.insert(p.indices.end(), {a, c, d, a, d, b});
    }
  }
  return p;
}

// Brute force: the largest distance from dense samples of `from` (8 x 8
// sub-triangles each plus the vertices) to the nearest triangle of `to`.
// A lower estimate of the one-sided Hausdorff distance, which the recorded
// bound must not be below.
float MeasuredDistance(const Primitive& p, const std::vector<uint32_t>& from,
                       const std::vector<uint32_t>& to) {
  float worst = 0.0f;
  constexpr int k = 8;
  for (size_t t = 0; t + 2 < from.size(); t += 3) {
    const glm::vec3 a = p.positions[from[t]], b = p.positions[from[t + 1]],
                    c = p.positions[from[t + 2]];
    for (int i = 0; i <= k; ++i) {
      for (int j = 0; i + j <= k; ++j) {
        const glm::vec3 x = a + (b - a) * (float(i) / k) + (c - a) * (float(j) / k);
        float nearest = INFINITY;
        for (size_t u = 0; u + 2 < to.size(); u += 3) {
          const glm::vec3 q = ClosestPointOnTriangle(x, p.positions[to[u]], p.positions[to[u + 1]],
                                                     p.positions[to[u + 2]]);
          nearest = std::min(nearest, glm::length(q - x));
        }
        worst = std::max(worst, nearest);
      }
    }
  }
  return worst;
}

void ExpectBoundsHold(const Primitive& p, size_t expected_levels) {
  const std::vector<ProxyLevel> levels = BuildProxyLevels(p);
  ASSERT_GE(levels.size(), expected_levels);
  const float diagonal = glm::length(p.bounds.extent());
  size_t finer = p.indices.size();
  for (size_t l = 0; l < levels.size(); ++l) {
    SCOPED_TRACE(::testing::Message() << "level " << l << ", " << levels[l].indices.size() / 3
                                      << " triangles, recorded error " << levels[l].error);
    // Each level at most half the one before; indices name real vertices.
    EXPECT_LE(levels[l].indices.size() * 2, finer);
    finer = levels[l].indices.size();
    for (uint32_t i : levels[l].indices) ASSERT_LT(i, p.positions.size());
    // The recorded bound: below the 2 % cap and at or above what the mesh
    // measures, both ways (exact up to float rounding: 1e-6 x diagonal).
    EXPECT_LT(levels[l].error, 0.02f * diagonal);
    const float there = MeasuredDistance(p, levels[l].indices, p.indices);
    const float back = MeasuredDistance(p, p.indices, levels[l].indices);
    EXPECT_LE(there, levels[l].error + 1e-6f * diagonal);
    EXPECT_LE(back, levels[l].error + 1e-6f * diagonal);
    // And not vacuous: within 4x the measured error plus the sampling
    // floor's covering radius (diagonal / 250 / sqrt(3)).
    EXPECT_LE(levels[l].error, 4.0f * std::max(there, back) + diagonal / 250.0f / std::sqrt(3.0f));
  }
}

TEST(ProxyLevels, SphereErrorWithinRecordedBound) { ExpectBoundsHold(Sphere(24, 48), 1); }

TEST(ProxyLevels, BumpyPlaneErrorWithinRecordedBound) { ExpectBoundsHold(BumpyPlane(40), 2); }

TEST(ProxyLevels, SmallOrDeformingPrimitivesKeepNone) {
  EXPECT_TRUE(BuildProxyLevels(Sphere(4, 8)).empty());  // 64 triangles
  Primitive skinned = Sphere(24, 48);
  skinned.joints.assign(skinned.positions.size(), glm::u16vec4(0));
  skinned.weights.assign(skinned.positions.size(), glm::vec4(1, 0, 0, 0));
  EXPECT_TRUE(BuildProxyLevels(skinned).empty());
}

TEST(ProxyLevels, PickTakesTheCoarsestLevelWithinTolerance) {
  std::vector<ProxyLevel> levels(3);
  levels[0].error = 0.001f;
  levels[1].error = 0.004f;
  levels[2].error = 0.016f;
  EXPECT_EQ(PickProxyLevel<ProxyLevel>(levels, 1.0f, 0.0005f), -1);
  EXPECT_EQ(PickProxyLevel<ProxyLevel>(levels, 1.0f, 0.001f), 0);
  EXPECT_EQ(PickProxyLevel<ProxyLevel>(levels, 1.0f, 0.01f), 1);
  EXPECT_EQ(PickProxyLevel<ProxyLevel>(levels, 2.0f, 0.01f), 1);  // 0.008 fits, 0.032 does not
  EXPECT_EQ(PickProxyLevel<ProxyLevel>(levels, 0.5f, 0.01f), 2);  // the instance is half size
}

TEST(ProxyLevels, MaxScaleBoundsTheStretch) {
  EXPECT_NEAR(MaxScale(glm::mat4(1.0f)), 1.0f, 1e-6f);
  const glm::mat4 rotated_scaled =
      glm::rotate(glm::scale(glm::mat4(1.0f), glm::vec3(3.0f)), 0.7f, glm::vec3(1, 2, 3));
  EXPECT_NEAR(MaxScale(rotated_scaled), 3.0f, 1e-5f);
  // Shear: never below the true largest stretch of a few directions.
  glm::mat4 shear(1.0f);
  shear[1][0] = 2.0f;
  const float bound = MaxScale(shear);
  for (const glm::vec3 d : {glm::vec3(0, 1, 0), glm::normalize(glm::vec3(1, 1, 0)),
                            glm::normalize(glm::vec3(0.4f, 0.9f, 0))}) {
    EXPECT_GE(bound, glm::length(glm::mat3(shear) * d) - 1e-6f);
  }
}

TEST(ProxyLevels, SceneMemoryCountsTheProxies) {
  Scene scene;
  scene.meshes.push_back({"sphere", {Sphere(24, 48)}});
  const SceneBytes without = CountSceneBytes(scene);
  BuildSceneProxies(&scene);
  size_t proxy_indices = 0;
  for (const ProxyLevel& l : scene.meshes[0].primitives[0].proxies) {
    proxy_indices += l.indices.size();
  }
  ASSERT_GT(proxy_indices, 0u);
  const SceneBytes with = CountSceneBytes(scene);
  EXPECT_EQ(with.cpu - without.cpu, proxy_indices * 4);
  EXPECT_EQ(with.gpu - without.gpu, proxy_indices * 4);
}

// Per-cluster levels: small leaves (256 triangles) so that the brute force
// stays quick and the trees have several levels of nodes.
std::vector<ProxyCluster> SmallClusters(const Primitive& p) {
  ClusterSettings settings;
  settings.leaf_triangles = 256;
  return BuildProxyClusters(p, settings);
}

// The edges used by exactly one triangle of `indices`, vertices identified
// by position (the sphere's seam repeats its vertices) and zero-area
// triangles left out (the simplifier drops them).
std::set<std::pair<uint32_t, uint32_t>> OpenEdges(const Primitive& p,
                                                  const std::vector<uint32_t>& indices) {
  std::map<std::tuple<float, float, float>, uint32_t> first;
  std::vector<uint32_t> weld(p.positions.size());
  for (size_t v = 0; v < p.positions.size(); ++v) {
    const glm::vec3& x = p.positions[v];
    weld[v] = first.emplace(std::make_tuple(x.x, x.y, x.z), uint32_t(v)).first->second;
  }
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const uint32_t v[3] = {weld[indices[t]], weld[indices[t + 1]], weld[indices[t + 2]]};
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;  // the poles' slivers
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = v[k], b = v[(k + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::set<std::pair<uint32_t, uint32_t>> open;
  for (const auto& [edge, count] : uses) {
    if (count == 1) open.insert(edge);
  }
  return open;
}

// The triangles a view draws when it takes node n's copy wherever `take(n)`
// says so and the copy exists, and opens the node otherwise (as
// GpuScene::Draw walks the tree).
template <typename Take>
std::vector<uint32_t> Cut(const std::vector<ProxyCluster>& tree, Take take) {
  std::vector<uint32_t> out;
  std::vector<int> open = {0};
  while (!open.empty()) {
    const int n = open.back();
    open.pop_back();
    const ProxyCluster& c = tree[size_t(n)];
    const std::vector<uint32_t>* drawn = nullptr;
    if (!c.level.indices.empty() && take(n)) {
      drawn = &c.level.indices;
    } else if (c.children[0] < 0) {
      drawn = &c.indices;
    } else {
      open.push_back(c.children[1]);
      open.push_back(c.children[0]);
      continue;
    }
    out.insert(out.end(), drawn->begin(), drawn->end());
  }
  return out;
}

void ExpectClusterBoundsHold(const Primitive& p) {
  const std::vector<ProxyCluster> tree = SmallClusters(p);
  ASSERT_GE(tree.size(), 7u);
  const float diagonal = glm::length(p.bounds.extent());
  EXPECT_EQ(ClusterTriangles(tree, 0).size(), p.indices.size());  // every triangle once
  size_t copies = 0;
  for (size_t n = 0; n < tree.size(); ++n) {
    const ProxyCluster& c = tree[n];
    const std::vector<uint32_t> full = ClusterTriangles(tree, int(n));
    // The box holds the node's triangles and its copy (whose vertices are
    // the primitive's own).
    for (const std::vector<uint32_t>* list : {&full, &c.level.indices}) {
      for (uint32_t i : *list) {
        ASSERT_LT(i, p.positions.size());
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(p.positions[i], c.bounds.min)) &&
                    glm::all(glm::lessThanEqual(p.positions[i], c.bounds.max)));
      }
    }
    if (c.level.indices.empty()) continue;
    ++copies;
    SCOPED_TRACE(::testing::Message()
                 << "node " << n << ", " << full.size() / 3 << " -> " << c.level.indices.size() / 3
                 << " triangles, recorded error " << c.level.error);
    EXPECT_LE(c.level.indices.size() * 2, full.size());
    EXPECT_LT(c.level.error, 0.02f * diagonal);
    // The copy against the node's own full triangles, both ways, by brute
    // force (exact up to float rounding: 1e-6 x diagonal).
    const float there = MeasuredDistance(p, c.level.indices, full);
    const float back = MeasuredDistance(p, full, c.level.indices);
    EXPECT_LE(there, c.level.error + 1e-6f * diagonal);
    EXPECT_LE(back, c.level.error + 1e-6f * diagonal);
  }
  EXPECT_GE(copies * 4, tree.size()) << "a quarter of the nodes or more should have a copy";
  // Locked borders: whichever nodes a view takes, the drawn surface has the
  // open edges of the full mesh and no others (no cracks between nodes).
  const auto open_full = OpenEdges(p, p.indices);
  EXPECT_EQ(OpenEdges(p, Cut(tree, [](int) { return true; })), open_full);
  EXPECT_EQ(OpenEdges(p, Cut(tree, [](int n) { return n % 3 != 0; })), open_full);
  EXPECT_EQ(OpenEdges(p, Cut(tree, [](int n) { return n % 2 == 1; })), open_full);
}

TEST(ProxyClusters, SphereErrorWithinRecordedBoundAndWatertight) {
  ExpectClusterBoundsHold(Sphere(24, 48));
}

TEST(ProxyClusters, BumpyPlaneErrorWithinRecordedBoundAndWatertight) {
  ExpectClusterBoundsHold(BumpyPlane(40));
}

TEST(ProxyClusters, SmallOrDeformingPrimitivesKeepNone) {
  EXPECT_TRUE(BuildProxyClusters(Sphere(24, 48)).empty());  // 2,304 triangles: one leaf's worth
  Primitive skinned = Sphere(64, 96);
  skinned.joints.assign(skinned.positions.size(), glm::u16vec4(0));
  skinned.weights.assign(skinned.positions.size(), glm::vec4(1, 0, 0, 0));
  EXPECT_TRUE(BuildProxyClusters(skinned).empty());
}

TEST(ProxyClusters, SceneMemoryCountsTheClusters) {
  Scene scene;
  scene.meshes.push_back({"sphere", {Sphere(64, 96)}});  // 12,288 triangles
  const SceneBytes without = CountSceneBytes(scene);
  BuildSceneProxies(&scene);
  const Primitive& p = scene.meshes[0].primitives[0];
  ASSERT_FALSE(p.clusters.empty());
  size_t indices = 0;
  for (const ProxyLevel& l : p.proxies) indices += l.indices.size();
  for (const ProxyCluster& c : p.clusters) indices += c.indices.size() + c.level.indices.size();
  const SceneBytes with = CountSceneBytes(scene);
  EXPECT_EQ(with.cpu - without.cpu, indices * 4 + p.clusters.size() * sizeof(ProxyCluster));
  EXPECT_EQ(with.gpu - without.gpu, indices * 4);
}

}  // namespace proxy_levels_test
}  // namespace gistream
