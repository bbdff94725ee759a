// sh_probes' probe cube maps from proxy geometry (issue 19): the probes'
// distance cubes drawn from the simplified levels and cluster copies match
// the full-detail cubes within one face texel's world size at each texel's
// distance, and forcing full detail draws exactly the cubes drawn before
// proxies existed (bitwise), as does per-face culling alone; the
// geometry-shader fallback draws the same cubes as the layered path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/proxy_filters.h"
#include "scene/gpu_scene.h"
#include "solvers/sh_probes/probe_grid.h"
#include "solvers/sh_probes/probe_raster.h"
#include "support/gl_context.h"
#include "support/test_meshes.h"

namespace gistream {
namespace {

// The floor and sphere scene of proxy_shadow_test.cpp (the sphere has a
// cluster tree: 9,216 triangles).
std::shared_ptr<const Scene> TestScene(bool with_proxies) {
  return testing::FloorAndSphereScene(40, 48, 96, with_proxies);
}

// sh_probes' default face size; a 4 x 4 x 4 grid over the scene's box.
ProbeGridSettings GridSettings() {
  ProbeGridSettings settings;
  settings.grid = 4;
  settings.face_size = 16;
  return settings;
}

class ShProbesProxyTest : public testing::GlContextTest {
 protected:
  // Every probe's distance cube (0: nothing hit), the atlas's six layers.
  std::vector<float> Distances(const std::shared_ptr<const Scene>& scene, bool full_detail,
                               int* proxied_pairs = nullptr, bool layered = true) {
    SceneState state(scene);
    auto gpu = GpuScene::Upload(state);
    EXPECT_TRUE(gpu.ok()) << gpu.status();
    if (!gpu.ok()) return {};
    auto layout = FitProbeGrid(scene->bounds, GridSettings());
    EXPECT_TRUE(layout.ok()) << layout.status();
    if (!layout.ok()) return {};
    layout_ = *layout;
    ProbeAtlas atlas;
    atlas.Allocate(layout_);
    auto raster = ProbeRasterizer::Create(layered);
    EXPECT_TRUE(raster.ok()) << raster.status();
    if (!raster.ok()) return {};
    EXPECT_EQ(raster->layered(), layered);
    raster->Draw(**gpu, state, layout_, atlas, nullptr, full_detail);
    std::vector<float> distance(size_t(layout_.texels()));
    glGetTextureImage(atlas.distance(), 0, GL_RED, GL_FLOAT,
                      GLsizei(distance.size() * sizeof(float)), distance.data());
    if (proxied_pairs) {
      // (probe, item) pairs whose nearest point allows a proxy level.
      *proxied_pairs = 0;
      for (int p = 0; p < layout_.probes(); ++p) {
        const glm::vec3 probe = layout_.position(layout_.cell(p));
        for (const DrawItem& d : (*gpu)->draws()) {
          const Bounds& b = scene->meshes[size_t(d.mesh)].primitives[size_t(d.primitive)].bounds;
          const float tolerance = CubeTexelTolerance(b, probe, layout_.face_size);
          if ((*gpu)->PickLevel(d, 1.0f, tolerance) >= 0) ++*proxied_pairs;
        }
      }
    }
    return distance;
  }

  // Texel (x, y) of face `face` of probe `probe`, nothing hit as +inf.
  float At(const std::vector<float>& distance, int probe, int face, int x, int y) const {
    const int n = layout_.face_size;
    x = std::clamp(x, 0, n - 1);
    y = std::clamp(y, 0, n - 1);
    const size_t column = size_t((probe % layout_.tiles_x) * n + x);
    const size_t row = size_t((probe / layout_.tiles_x) * n + y);
    const float d =
        distance[(size_t(face) * size_t(layout_.height()) + row) * size_t(layout_.width()) +
                 column];
    return d > 0.0f ? d : std::numeric_limits<float>::infinity();
  }

  ProbeLayout layout_;
};

TEST_F(ShProbesProxyTest, ProxyCubesMatchFullDetailWithinOneTexel) {
  const auto scene = TestScene(true);
  int proxied = 0;
  const std::vector<float> full = Distances(scene, true);
  const std::vector<float> proxy = Distances(scene, false, &proxied);
  ASSERT_EQ(full.size(), proxy.size());
  ASSERT_FALSE(full.empty());
  ASSERT_GE(proxied, layout_.probes()) << "proxies should be drawn, or the test shows nothing";
  EXPECT_NE(full, proxy) << "the proxies drew the full meshes";
  // A face texel's world size at distance d: 2 d / N (the face-centre
  // texel, the smallest). Every texel either cube covers holds a proxy
  // distance within that of the full-detail range over its 3 x 3
  // neighbourhood in the face (one texel of position: on silhouettes and
  // grazing surfaces a texel's shift changes the distance by more than a
  // texel), and nearly all match at the same texel.
  const int n = layout_.face_size;
  size_t covered = 0, same_texel = 0;
  float worst = 0.0f;
  for (int p = 0; p < layout_.probes(); ++p) {
    for (int f = 0; f < 6; ++f) {
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          const float d_full = At(full, p, f, x, y), d_proxy = At(proxy, p, f, x, y);
          if (std::isinf(d_full) && std::isinf(d_proxy)) continue;  // nothing in either
          ++covered;
          const float texel = 2.0f * std::min(d_full, d_proxy) / float(n);
          if (std::abs(d_proxy - d_full) <= texel) ++same_texel;
          float lo = d_full, hi = d_full;
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
              lo = std::min(lo, At(full, p, f, x + dx, y + dy));
              hi = std::max(hi, At(full, p, f, x + dx, y + dy));
            }
          }
          const float outside = std::max({lo - d_proxy, d_proxy - hi, 0.0f});
          worst = std::max(worst, outside / texel);
          EXPECT_LE(outside, texel) << "probe " << p << " face " << f << " texel " << x << "," << y
                                    << ": " << d_full << " vs " << d_proxy;
        }
      }
    }
  }
  // The floor and sphere fill about half of every probe's directions.
  EXPECT_GT(covered, layout_.texels() / 4);
  EXPECT_GE(double(same_texel), 0.99 * double(covered));
  RecordProperty("worst_error_in_texels", std::to_string(worst));
  RecordProperty("same_texel_fraction", std::to_string(double(same_texel) / double(covered)));
}

TEST_F(ShProbesProxyTest, FullDetailAndCullingDrawTheCubesOfBeforeProxies) {
  // Before proxies: no levels, every probe's faces in one instanced draw.
  const std::vector<float> before = Distances(TestScene(false), true);
  ASSERT_FALSE(before.empty());
  // full_detail on a scene with proxies: the same draw.
  EXPECT_EQ(Distances(TestScene(true), true), before);
  // Per-probe draws culled per face (a scene without proxies, full_detail
  // off) leave out only what a face cannot see.
  EXPECT_EQ(Distances(TestScene(false), false), before);
}

TEST_F(ShProbesProxyTest, GeometryShaderFallbackDrawsTheSameCubes) {
  // Drivers without ARB_shader_viewport_layer_array draw the cubes with
  // rasterize.geom.glsl (six invocations per triangle, the face mask
  // tested there): the same face projection, so the same distances, with
  // proxies (one draw per probe) and in full.
  const auto scene = TestScene(true);
  for (const bool full_detail : {false, true}) {
    const std::vector<float> layered = Distances(scene, full_detail);
    const std::vector<float> geometry = Distances(scene, full_detail, nullptr, false);
    ASSERT_EQ(layered.size(), geometry.size());
    EXPECT_EQ(layered, geometry) << "full_detail " << full_detail;
  }
}

}  // namespace
}  // namespace gistream
