// sh_probes' probe cube maps from proxy geometry (issue 19): the probes'
// distance cubes drawn from the simplified levels and cluster copies match
// the full-detail cubes within one face texel's world size at each texel's
// distance, and forcing full detail draws exactly the cubes drawn before
// proxies existed (bitwise), as does per-face culling alone; the
// geometry-shader fallback draws the same cubes as the layered path; and
// the draw list the solver draws from gives the cubes GpuScene::Draw draws
// item by item.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "render/proxy_filters.h"
#include "scene/gpu/gpu_scene.h"
#include "solvers/sh_probes/probe_grid.h"
#include "solvers/sh_probes/probe_raster.h"
#include "support/gl_context.h"
#include "support/test_meshes.h"

namespace gistream {
namespace sh_probes_proxy_test {

// The floor and sphere scene of proxy_shadow_test.cpp (the sphere has a
// cluster tree: 9,216 triangles).
std::shared_ptr<const Scene> TestScene(bool with_proxies) {
  return testing::FloorAndSphereScene(40, 48, 96, with_proxies);
}

// The same with materials: a checker-textured floor, a sphere with a
// second texture, and a third, untextured material on a sphere instance:
// three texture sets (draw-list groups).
std::shared_ptr<const Scene> TexturedScene() {
  Scene scene = *TestScene(true);
  for (int i = 0; i < 2; ++i) {
    Image image;
    image.name = i == 0 ? "checker" : "stripes";
    image.width = image.height = 4;
    for (int y = 0; y < 4; ++y) {
      for (int x = 0; x < 4; ++x) {
        const bool on = i == 0 ? (x + y) % 2 == 0 : x % 2 == 0;
        const uint8_t rgba[4] = {uint8_t(on ? 230 : 40), uint8_t(i == 0 ? 90 : 200),
                                 uint8_t(on ? 30 : 180), 255};
        image.pixels8.insert(image.pixels8.end(), rgba, rgba + 4);
      }
    }
    scene.images.push_back(std::move(image));
    Material material;
    material.name = image.name;
    material.base_color_texture = i;
    scene.materials.push_back(material);
  }
  Material plain;
  plain.name = "plain";
  plain.base_color_factor = glm::vec4(0.2f, 0.7f, 0.3f, 1.0f);
  scene.materials.push_back(plain);
  scene.meshes[0].primitives[0].material = 0;
  scene.meshes[1].primitives[0].material = 1;
  // A second sphere, its own mesh (so its own material), beside the first.
  Mesh plain_sphere = scene.meshes[1];
  plain_sphere.primitives[0].material = 2;
  scene.meshes.push_back(std::move(plain_sphere));
  Node node;
  node.mesh = 2;
  node.translation = glm::vec3(0.6f, 0.0f, 0.3f);
  scene.nodes.push_back(node);
  scene.roots.push_back(int(scene.nodes.size()) - 1);
  scene.bounds.Extend(scene.meshes[2].primitives[0].bounds.Transformed(
      glm::translate(glm::mat4(1.0f), node.translation)));
  return std::make_shared<const Scene>(std::move(scene));
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
  struct Cubes {
    std::vector<float> distance;  // 0: nothing hit
    std::vector<float> normal;    // RGBA, w = 1: back face
    std::vector<float> albedo;    // RGBA
  };

  // Every probe's distance cube (0: nothing hit), the atlas's six layers.
  std::vector<float> Distances(const std::shared_ptr<const Scene>& scene, bool full_detail,
                               int* proxied_pairs = nullptr, bool layered = true) {
    return Draw(scene, full_detail, {.allow_layered = layered}, proxied_pairs).distance;
  }

  // Every probe's cube maps, drawn by a ProbeRasterizer with `options`.
  Cubes Draw(const std::shared_ptr<const Scene>& scene, bool full_detail,
             const ProbeRasterizer::Options& options, int* proxied_pairs = nullptr) {
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
    auto raster = ProbeRasterizer::Create(options);
    EXPECT_TRUE(raster.ok()) << raster.status();
    if (!raster.ok()) return {};
    EXPECT_EQ(raster->layered(), options.allow_layered);
    raster->Draw(**gpu, state, layout_, atlas, nullptr, full_detail);
    Cubes cubes;
    cubes.distance.resize(size_t(layout_.texels()));
    glGetTextureImage(atlas.distance(), 0, GL_RED, GL_FLOAT,
                      GLsizei(cubes.distance.size() * sizeof(float)), cubes.distance.data());
    cubes.normal.resize(size_t(layout_.texels()) * 4);
    glGetTextureImage(atlas.normal(), 0, GL_RGBA, GL_FLOAT,
                      GLsizei(cubes.normal.size() * sizeof(float)), cubes.normal.data());
    cubes.albedo.resize(size_t(layout_.texels()) * 4);
    glGetTextureImage(atlas.albedo(), 0, GL_RGBA, GL_FLOAT,
                      GLsizei(cubes.albedo.size() * sizeof(float)), cubes.albedo.data());
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
    return cubes;
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
  // Before proxies: no levels, every probe's faces in full.
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
  // rasterize.geom.glsl (each triangle into its record's face): the same
  // face projection, so the same distances, with proxies and in full.
  const auto scene = TestScene(true);
  for (const bool full_detail : {false, true}) {
    const std::vector<float> layered = Distances(scene, full_detail);
    const std::vector<float> geometry = Distances(scene, full_detail, nullptr, false);
    ASSERT_EQ(layered.size(), geometry.size());
    EXPECT_EQ(layered, geometry) << "full_detail " << full_detail;
  }
}

TEST_F(ShProbesProxyTest, DrawListCubesAreTheItemByItemCubes) {
  // The solver draws each probe from an indirect draw list (a record per
  // face that may see a node, textures bound per group, the material from
  // the record); GpuScene::Draw item by item with the same filters is the
  // reference. Same positions, so the distances and albedos are bitwise
  // equal; the normal comes through the model's cofactor matrix instead of
  // the CPU's inverse transpose, so it may differ by rounding: within one
  // step of the 8-bit snorm normal, the back-face flag equal.
  const auto scene = TexturedScene();
  for (const bool layered : {true, false}) {
    for (const bool full_detail : {false, true}) {
      SCOPED_TRACE(std::string(layered ? "layered" : "geometry shader") +
                   (full_detail ? ", full detail" : ", proxies"));
      const Cubes by_list = Draw(scene, full_detail, {.allow_layered = layered});
      const Cubes by_item =
          Draw(scene, full_detail, {.allow_layered = layered, .draw_list = false});
      ASSERT_FALSE(by_item.distance.empty());
      size_t covered = 0;
      for (float d : by_item.distance) covered += d > 0.0f ? 1 : 0;
      EXPECT_GT(covered, by_item.distance.size() / 4) << "the cubes show the scene";
      EXPECT_EQ(by_list.distance, by_item.distance);
      EXPECT_EQ(by_list.albedo, by_item.albedo);
      // Every material shows (a wrong record material or texture binding
      // would change the albedos above): the green of the plain one.
      size_t plain = 0;
      for (size_t i = 0; i < by_item.albedo.size(); i += 4) {
        plain += std::abs(by_item.albedo[i + 1] - 0.7f) < 0.01f ? 1 : 0;
      }
      EXPECT_GT(plain, 0u);
      ASSERT_EQ(by_list.normal.size(), by_item.normal.size());
      float worst = 0.0f;
      size_t flags_differ = 0;
      for (size_t i = 0; i < by_item.normal.size(); i += 4) {
        for (size_t c = 0; c < 3; ++c) {
          worst = std::max(worst, std::abs(by_list.normal[i + c] - by_item.normal[i + c]));
        }
        flags_differ += by_list.normal[i + 3] != by_item.normal[i + 3] ? 1 : 0;
      }
      EXPECT_LE(worst, 1.0f / 127.0f + 1e-6f);
      EXPECT_EQ(flags_differ, 0u);
    }
  }
}

}  // namespace sh_probes_proxy_test
}  // namespace gistream
