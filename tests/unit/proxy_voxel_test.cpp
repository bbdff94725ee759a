// avg's voxelization from proxy geometry (issue 19): a grid built from the
// simplified levels (each within half a voxel) marks the voxels of the
// full-detail grid up to one voxel at surface edges, and full_detail builds
// exactly the grid of a scene without proxies.
#include <gtest/gtest.h>

#include <cmath>

#include "scene/proxy_levels.h"
#include "solvers/avg/voxel_grid.h"

namespace gistream::avg {
namespace {

// A sphere of radius 0.3 (64 x 128 quads) over a 48 x 48 floor.
std::shared_ptr<const Scene> TestScene(bool with_proxies) {
  Scene scene;
  Primitive floor, sphere;
  constexpr int n = 48;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const glm::vec3 v(-1.0f + 2.0f * float(i) / n, 0.0f, -1.0f + 2.0f * float(j) / n);
      floor.positions.push_back(v);
      floor.normals.push_back({0, 1, 0});
      floor.bounds.Extend(v);
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + n + 1, d = c + 1;
      floor.indices.insert(floor.indices.end(), {a, c, d, a, d, b});
    }
  }
  constexpr int rings = 64, segments = 128;
  for (int r = 0; r <= rings; ++r) {
    const float theta = float(M_PI) * float(r) / rings;
    for (int s = 0; s <= segments; ++s) {
      const float phi = 2.0f * float(M_PI) * float(s) / segments;
      const glm::vec3 unit(std::sin(theta) * std::cos(phi), std::cos(theta),
                           std::sin(theta) * std::sin(phi));
      sphere.positions.push_back(glm::vec3(0.0f, 0.5f, 0.0f) + 0.3f * unit);
      sphere.normals.push_back(unit);
      sphere.bounds.Extend(sphere.positions.back());
    }
  }
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = uint32_t(r * (segments + 1) + s), b = a + 1, c = a + segments + 1,
                     d = c + 1;
      sphere.indices.insert(sphere.indices.end(), {a, c, d, a, d, b});
    }
  }
  scene.meshes.push_back({"floor", {floor}});
  scene.meshes.push_back({"sphere", {sphere}});
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

// Whether `grid` has a filled voxel within one voxel (26-neighbourhood) of v.
bool FilledNear(const VoxelGrid& grid, const glm::ivec3& v) {
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (grid.Filled(v + glm::ivec3(dx, dy, dz))) return true;
      }
    }
  }
  return false;
}

TEST(ProxyVoxels, ProxyGridMatchesFullDetailWithinOneVoxel) {
  constexpr int kResolution = 64;
  const auto scene = TestScene(true);
  const SceneState state(scene);
  const VoxelGrid full = VoxelGrid::Build(state, kResolution, /*full_detail=*/true);
  const VoxelGrid proxy = VoxelGrid::Build(state, kResolution);
  // Both meshes have a level within half a voxel, or this shows nothing.
  const float tolerance =
      0.5f * std::min({full.voxel_size().x, full.voxel_size().y, full.voxel_size().z});
  for (const Mesh& mesh : scene->meshes) {
    EXPECT_GE(PickProxyLevel<ProxyLevel>(mesh.primitives[0].proxies, 1.0f, tolerance), 0)
        << mesh.name;
  }
  size_t same = 0, filled = 0;
  glm::ivec3 v;
  for (v.z = 0; v.z < kResolution; ++v.z) {
    for (v.y = 0; v.y < kResolution; ++v.y) {
      for (v.x = 0; v.x < kResolution; ++v.x) {
        if (!full.Filled(v) && !proxy.Filled(v)) continue;
        ++filled;
        same += full.Filled(v) == proxy.Filled(v) ? 1 : 0;
        if (full.Filled(v)) {
          EXPECT_TRUE(FilledNear(proxy, v)) << v.x << "," << v.y << "," << v.z;
        }
        if (proxy.Filled(v)) {
          EXPECT_TRUE(FilledNear(full, v)) << v.x << "," << v.y << "," << v.z;
        }
        if (full.Filled(v) && proxy.Filled(v)) {
          // The same surface: normals agree where both have one.
          const glm::vec3 a = full.Normal(v), b = proxy.Normal(v);
          if (a != glm::vec3(0.0f) && b != glm::vec3(0.0f)) {
            EXPECT_GT(glm::dot(a, b), 0.9f);
          }
        }
      }
    }
  }
  // Nearly every voxel is the same; the rest are single-voxel edge shifts.
  EXPECT_GE(double(same), 0.97 * double(filled));
  RecordProperty("same_fraction", std::to_string(double(same) / double(filled)));
}

TEST(ProxyVoxels, FullDetailBuildsTheGridOfBeforeProxies) {
  constexpr int kResolution = 48;
  const SceneState with(TestScene(true)), without(TestScene(false));
  const VoxelGrid a = VoxelGrid::Build(with, kResolution, /*full_detail=*/true);
  const VoxelGrid b = VoxelGrid::Build(without, kResolution);
  ASSERT_EQ(a.filled(), b.filled());
  glm::ivec3 v;
  for (v.z = 0; v.z < kResolution; ++v.z) {
    for (v.y = 0; v.y < kResolution; ++v.y) {
      for (v.x = 0; v.x < kResolution; ++v.x) {
        ASSERT_EQ(a.at(v).count, b.at(v).count);
        ASSERT_EQ(a.at(v).normal_sum, b.at(v).normal_sum);
        ASSERT_EQ(a.at(v).point_sum, b.at(v).point_sum);
      }
    }
  }
}

}  // namespace
}  // namespace gistream::avg
