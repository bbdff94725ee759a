// Proxy levels (issue 19): each simplified level's geometric error, measured
// here on the mesh by brute force, is within the bound import recorded.
#include "scene/proxy_levels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/scene_memory.h"
#include "scene/surface_distance.h"

namespace gistream {
namespace {

// A UV sphere of radius 1 (rings x segments quads, poles included): curved
// everywhere, so every simplified level has a real error.
Primitive Sphere(int rings, int segments) {
  Primitive p;
  for (int r = 0; r <= rings; ++r) {
    const float theta = float(M_PI) * float(r) / float(rings);
    for (int s = 0; s <= segments; ++s) {
      const float phi = 2.0f * float(M_PI) * float(s) / float(segments);
      const glm::vec3 v(std::sin(theta) * std::cos(phi), std::cos(theta),
                        std::sin(theta) * std::sin(phi));
      p.positions.push_back(v);
      p.normals.push_back(v);
      p.bounds.Extend(v);
    }
  }
  const auto at = [&](int r, int s) { return uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      p.indices.insert(p.indices.end(), {at(r, s), at(r + 1, s), at(r + 1, s + 1)});
      p.indices.insert(p.indices.end(), {at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
  }
  return p;
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
    SCOPED_TRACE(testing::Message() << "level " << l << ", " << levels[l].indices.size() / 3
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

}  // namespace
}  // namespace gistream
