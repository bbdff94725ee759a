// avg's voxelization from proxy geometry (issue 19): a grid built from the
// simplified levels (each within half a voxel) marks the voxels of the
// full-detail grid up to one voxel at surface edges, and full_detail builds
// exactly the grid of a scene without proxies.
#include <gtest/gtest.h>

#include <cmath>

#include "scene/proxies/proxy_levels.h"
#include "solvers/avg/voxel_grid.h"
#include "support/test_meshes.h"

namespace gistream::avg {
namespace proxy_voxel_test {

// A sphere of radius 0.3 (64 x 128 quads) over a 48 x 48 floor.
std::shared_ptr<const Scene> TestScene(bool with_proxies) {
  return gistream::testing::FloorAndSphereScene(48, 64, 128, with_proxies);
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

}  // namespace proxy_voxel_test
}  // namespace gistream::avg
