// avg's VPL paraboloid maps from proxy geometry (issue 19): maps drawn from
// the simplified levels match the full-detail maps within one map texel's
// world size at each texel's distance, and forcing full detail draws
// exactly the maps drawn before proxies existed (bitwise).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "render/proxy_filters.h"
#include "render/shadow_maps.h"
#include "scene/gpu/gpu_scene.h"
#include "solvers/avg/vpl_shadow_maps.h"
#include "support/gl_context.h"
#include "support/test_meshes.h"

namespace gistream {
namespace avg_proxy_maps_test {

constexpr int kResolution = 64;  // avg's default shadow_res

// The floor and sphere scene of proxy_shadow_test.cpp.
std::shared_ptr<const Scene> TestScene(bool with_proxies) {
  return testing::FloorAndSphereScene(40, 48, 96, with_proxies);
}

// Above the sphere looking down, on the floor beside it looking up, to its
// side looking along +x (the floor half behind it is culled), and 0.6 above
// the floor looking down: there the floor's coarsest level (a few
// triangles across it) is within 2 d / N, and its edges run out to the
// map's rim, where straight edges drawn into the paraboloid map itself
// would land many texels off their true curves (557 texels failed so).
std::vector<avg::Vpl> TestVpls() {
  std::vector<avg::Vpl> vpls(4);
  vpls[0].position = {0.3f, 4.0f, 0.2f};
  vpls[0].normal = {0.0f, -1.0f, 0.0f};
  vpls[1].position = {0.7f, 0.01f, -0.1f};
  vpls[1].normal = {0.0f, 1.0f, 0.0f};
  vpls[2].position = {-4.0f, 0.5f, 0.1f};
  vpls[2].normal = {1.0f, 0.0f, 0.0f};
  vpls[3].position = {0.9f, 0.6f, 0.3f};
  vpls[3].normal = {0.0f, -1.0f, 0.0f};
  return vpls;
}

class AvgProxyMapsTest : public testing::GlContextTest {
 protected:
  // Every VPL's map as distances (depth x its far), layer by layer.
  std::vector<float> Maps(const std::shared_ptr<const Scene>& scene, bool full_detail,
                          int* proxied_items = nullptr) {
    SceneState state(scene);
    auto gpu = GpuScene::Upload(state);
    EXPECT_TRUE(gpu.ok()) << gpu.status();
    if (!gpu.ok()) return {};
    auto maps = avg::VplShadowMaps::Create();
    EXPECT_TRUE(maps.ok()) << maps.status();
    if (!maps.ok()) return {};
    const std::vector<avg::Vpl> vpls = TestVpls();
    maps->Upload(vpls, scene->bounds);
    maps->Render(**gpu, state, kResolution, full_detail);
    std::vector<float> depth(vpls.size() * kResolution * kResolution);
    glGetTextureImage(maps->maps().id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                      GLsizei(depth.size() * sizeof(float)), depth.data());
    far_.clear();
    for (size_t v = 0; v < vpls.size(); ++v) {
      far_.push_back(ShadowFar(scene->bounds, vpls[v].position));
      for (size_t i = 0; i < size_t(kResolution) * kResolution; ++i) {
        depth[v * kResolution * kResolution + i] *= far_.back();
      }
    }
    if (proxied_items) {
      // (item, VPL) pairs whose nearest point allows a proxy level.
      *proxied_items = 0;
      for (const avg::Vpl& v : vpls) {
        for (const DrawItem& d : (*gpu)->draws()) {
          const Bounds& b = scene->meshes[size_t(d.mesh)].primitives[size_t(d.primitive)].bounds;
          const float tolerance = ParaboloidTexelTolerance(b, v.position, v.normal, kResolution);
          if (tolerance >= 0.0f && (*gpu)->PickLevel(d, 1.0f, tolerance) >= 0) ++*proxied_items;
        }
      }
    }
    return depth;
  }

  std::vector<float> far_;
};

TEST_F(AvgProxyMapsTest, ProxyMapsMatchFullDetailWithinOneTexel) {
  const auto scene = TestScene(true);
  int proxied = 0;
  const std::vector<float> full = Maps(scene, true);
  const std::vector<float> proxy = Maps(scene, false, &proxied);
  ASSERT_EQ(full.size(), proxy.size());
  ASSERT_GE(proxied, 2) << "proxy levels should be drawn, or the test shows nothing";
  // A paraboloid texel subtends at most 4 / N radians (on the axis,
  // render/proxy_filters.h): its world size at distance d is at most 4 d /
  // N. Every covered texel holds a proxy distance within that of the
  // full-detail range over its 3 x 3 neighbourhood (silhouettes and steep
  // slopes move by more than a texel under one texel's shift), and most
  // match at the same texel: the proxies are drawn into a cube and
  // resampled (a map texel takes the cube texel its centre falls in, whose
  // centre ray is up to 0.71 of a face texel away; measured 96 %).
  size_t covered = 0, same_texel = 0;
  float worst = 0.0f;
  for (size_t v = 0; v < far_.size(); ++v) {
    const float* f = full.data() + v * kResolution * kResolution;
    const float* p = proxy.data() + v * kResolution * kResolution;
    for (int y = 0; y < kResolution; ++y) {
      for (int x = 0; x < kResolution; ++x) {
        const size_t i = size_t(y) * kResolution + size_t(x);
        if (f[i] >= far_[v] && p[i] >= far_[v]) continue;  // nothing in either
        ++covered;
        const float texel = 4.0f * std::min(f[i], p[i]) / kResolution;
        if (std::abs(p[i] - f[i]) <= texel) ++same_texel;
        float lo = f[i], hi = f[i];
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = std::clamp(x + dx, 0, kResolution - 1);
            const int yy = std::clamp(y + dy, 0, kResolution - 1);
            lo = std::min(lo, f[size_t(yy) * kResolution + size_t(xx)]);
            hi = std::max(hi, f[size_t(yy) * kResolution + size_t(xx)]);
          }
        }
        const float outside = std::max({lo - p[i], p[i] - hi, 0.0f});
        worst = std::max(worst, outside / texel);
        EXPECT_LE(outside, texel) << "VPL " << v << " texel " << x << "," << y << ": " << f[i]
                                  << " vs " << p[i];
      }
    }
  }
  // From 4 units the scene is small in a paraboloid map (~1/20 of it).
  EXPECT_GT(covered, size_t(200));
  EXPECT_GE(double(same_texel), 0.9 * double(covered));
  RecordProperty("worst_error_in_texels", std::to_string(worst));
  RecordProperty("same_texel_fraction", std::to_string(double(same_texel) / double(covered)));
}

// The distance cubes are bounded before they are made, and the memory
// estimate (avg_estimates.cpp) counts what the maps hold: 64 VPLs a batch at
// the default shadow_res, fewer where 64 cubes would pass 64 MiB (a batch
// of 64 cubes of 512^2 faces would be 403 MB per atlas).
TEST(AvgDistanceCubes, BatchIsBoundedAndCountedInGpuBytes) {
  EXPECT_EQ(avg::VplShadowMaps::CubeBatch(64, 1024), 64);
  EXPECT_EQ(avg::VplShadowMaps::CubeBatch(64, 3), 3);
  EXPECT_EQ(avg::VplShadowMaps::CubeBatch(512, 1024), 10);
  EXPECT_EQ(avg::VplShadowMaps::CubeBatch(8192, 1024), 1);
  EXPECT_LE(avg::VplShadowMaps::CubeBatchBytes(512, 1024), uint64_t(64) << 20);
}

TEST_F(AvgProxyMapsTest, CubesAreCountedInGpuBytes) {
  const auto scene = TestScene(true);
  SceneState state(scene);
  auto gpu = GpuScene::Upload(state);
  ASSERT_TRUE(gpu.ok()) << gpu.status();
  auto maps = avg::VplShadowMaps::Create();
  ASSERT_TRUE(maps.ok()) << maps.status();
  const std::vector<avg::Vpl> vpls = TestVpls();
  maps->Upload(vpls, scene->bounds);
  const uint64_t before = maps->gpu_bytes();  // the VPL buffer
  maps->Render(**gpu, state, kResolution, false);
  const uint64_t atlas = vpls.size() * kResolution * kResolution * 4;
  EXPECT_EQ(maps->gpu_bytes() - before,
            atlas + avg::VplShadowMaps::CubeBatchBytes(kResolution, int(vpls.size())));
}

TEST_F(AvgProxyMapsTest, FullDetailDrawsTheMapsOfBeforeProxies) {
  // Before proxies: no levels, one instanced draw per item for all VPLs.
  const std::vector<float> before = Maps(TestScene(false), true);
  ASSERT_FALSE(before.empty());
  // full_detail on a scene with proxies: the same draws.
  EXPECT_EQ(Maps(TestScene(true), true), before);
  // A scene without proxies and full_detail off: nothing to coarsen.
  EXPECT_EQ(Maps(TestScene(false), false), before);
}

}  // namespace avg_proxy_maps_test
}  // namespace gistream
