// Element hierarchies from proxy levels (issue 19): `implicit_visibility`
// and `antiradiance` make their elements from the coarsest proxy level
// within a tenth of the element size (hierarchy/element_source.h).
// full_detail builds exactly the elements of before proxies; a finely
// tessellated flat room lit through its proxies gives the image of the
// coarse original; the display from proxy elements has no black or
// non-finite pixel where full detail has light.
#include <cstring>
#include <map>
#include <string>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "gl/stage_timer.h"
#include "scene/gpu/gpu_scene.h"
#include "solvers/antiradiance/shared_elements.h"
#include "solvers/hierarchy/subdivide.h"
#include "solvers/implicit_visibility/scene_elements.h"
#include "support/gl_context.h"
#include "support/gltf_builder.h"
#include "support/measurement.h"
#include "support/render_helpers.h"
#include "support/test_meshes.h"

namespace gistream {
namespace proxy_elements_test {

using testing::FloatImage;

template <typename T>
bool SameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

class ProxyElementsTest : public testing::GlContextTest {
 protected:
  static SceneElements Build(const std::shared_ptr<const Scene>& scene, bool full_detail) {
    SceneState state(scene);
    auto gpu = GpuScene::Upload(state);
    EXPECT_TRUE(gpu.ok()) << gpu.status();
    SceneElements elements;
    if (!gpu.ok()) return elements;
    gl::StageTimer timer;
    elements.Build(state, **gpu, timer, full_detail);
    elements.UpdateGeometry(state);
    return elements;
  }

  static antiradiance::Patches Patches(const std::shared_ptr<const Scene>& scene,
                                       bool full_detail) {
    SceneState state(scene);
    auto gpu = GpuScene::Upload(state);
    EXPECT_TRUE(gpu.ok()) << gpu.status();
    if (!gpu.ok()) return {};
    antiradiance::SurfelCache cache;
    return antiradiance::SurfelPatches(state, **gpu, cache, full_detail);
  }
};

// The memory estimate counts the elements of the level the builder takes:
// counting the full mesh refused the 594K-triangle atrium for
// implicit_visibility at 24 GiB (RESULTS.md, the atrium eval).
TEST_F(ProxyElementsTest, MemoryEstimateCountsTheProxyLevelsElements) {
  const auto with = testing::FloorAndSphereScene(40, 48, 96, true);
  const SceneElements full = Build(with, true);
  const SceneElements proxied = Build(with, false);
  ASSERT_GT(proxied.proxy_leaves(), 0);
  SceneState state(with);
  auto gpu = GpuScene::Upload(state);
  ASSERT_TRUE(gpu.ok()) << gpu.status();
  const uint64_t full_bound = hierarchy::SubdividedVertexBound(state, **gpu, true);
  const uint64_t proxy_bound = hierarchy::SubdividedVertexBound(state, **gpu, false);
  const uint64_t full_leaves = uint64_t(full.elements().leaf_count());
  const uint64_t proxy_leaves = uint64_t(proxied.elements().leaf_count());
  // An upper bound on what each build makes, within 4x of it.
  EXPECT_GE(full_bound, full_leaves);
  EXPECT_LE(full_bound, 4 * full_leaves);
  EXPECT_GE(proxy_bound, proxy_leaves);
  // Measured: 6,434 leaves and bound in full; 2,028 leaves, bound 3,406
  // from the levels. Counting the full mesh (6,434) fails this.
  EXPECT_LE(proxy_bound, 2 * proxy_leaves) << "the levels' elements are counted, not the mesh's";
}

TEST_F(ProxyElementsTest, FullDetailBuildsTheElementsOfBeforeProxies) {
  // The floor-and-sphere scene of ProxyShadowTest (both meshes get
  // proxies), with and without its levels.
  const auto with = testing::FloorAndSphereScene(40, 48, 96, true);
  const auto without = testing::FloorAndSphereScene(40, 48, 96, false);
  const SceneElements before = Build(without, false);
  const SceneElements full = Build(with, true);
  const SceneElements proxied = Build(with, false);
  EXPECT_EQ(full.proxy_leaves(), 0);
  const hierarchy::Elements& a = full.elements();
  const hierarchy::Elements& b = before.elements();
  EXPECT_EQ(a.leaf_count(), b.leaf_count());
  EXPECT_TRUE(SameBytes(a.position, b.position));
  EXPECT_TRUE(SameBytes(a.normal, b.normal));
  EXPECT_TRUE(SameBytes(a.area, b.area));
  EXPECT_TRUE(SameBytes(a.radius, b.radius));
  EXPECT_TRUE(SameBytes(a.cone, b.cone));
  EXPECT_TRUE(SameBytes(a.slab, b.slab));
  EXPECT_TRUE(SameBytes(a.parent, b.parent));
  EXPECT_TRUE(SameBytes(a.children, b.children));
  EXPECT_TRUE(SameBytes(a.roots(), b.roots()));
  EXPECT_TRUE(SameBytes(full.triangles(), before.triangles()));
  EXPECT_TRUE(SameBytes(full.vertex_world(), before.vertex_world()));
  EXPECT_TRUE(SameBytes(full.vertex_leaves(), before.vertex_leaves()));
  EXPECT_TRUE(SameBytes(full.vertex_weights(), before.vertex_weights()));
  // Without full_detail the proxies are used: fewer leaves, the same
  // display mesh (the full one) with its vertices transferred.
  EXPECT_GT(proxied.proxy_leaves(), 0);
  EXPECT_LT(proxied.elements().leaf_count(), before.elements().leaf_count());
  EXPECT_EQ(proxied.triangles(), before.triangles());
  EXPECT_EQ(proxied.vertex_world(), before.vertex_world());
  testing::RecordMeasurement("leaves_full", b.leaf_count());
  testing::RecordMeasurement("leaves_proxy", proxied.elements().leaf_count());

  // antiradiance's patches from the shared hierarchy, the same way.
  const antiradiance::Patches pb = Patches(without, false);
  const antiradiance::Patches pf = Patches(with, true);
  EXPECT_TRUE(SameBytes(pf.position, pb.position));
  EXPECT_TRUE(SameBytes(pf.normal, pb.normal));
  EXPECT_TRUE(SameBytes(pf.area, pb.area));
  EXPECT_TRUE(SameBytes(pf.radius, pb.radius));
  EXPECT_TRUE(SameBytes(pf.albedo, pb.albedo));
  EXPECT_TRUE(SameBytes(pf.tag, pb.tag));
  EXPECT_TRUE(SameBytes(pf.children, pb.children));
  EXPECT_TRUE(SameBytes(pf.roots, pb.roots));
  EXPECT_TRUE(SameBytes(pf.cell, pb.cell));
  EXPECT_TRUE(SameBytes(pf.cell_begin, pb.cell_begin));
  EXPECT_LT(Patches(with, false).size(), pb.size());
}

// An open box (2 m, white floor, ceiling and back, red left and green
// right wall) lit by a point light, each wall n x n quads; with `block`, a
// white block (0.5 x 0.8 x 0.5 m, five faces of n x n quads) on the floor.
std::string FlatRoom(int n, bool block = false) {
  testing::GltfBuilder b;
  const int white = b.AddMaterial("white", {0.7f, 0.7f, 0.7f});
  const int red = b.AddMaterial("red", {0.7f, 0.1f, 0.1f});
  const int green = b.AddMaterial("green", {0.1f, 0.7f, 0.1f});
  b.AddQuad("floor", {0, -1, 0}, {0, 0, 1}, {1, 0, 0}, white, n);
  b.AddQuad("ceiling", {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, white, n);
  b.AddQuad("back", {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, white, n);
  b.AddQuad("left", {-1, 0, 0}, {0, 1, 0}, {0, 0, 1}, red, n);
  b.AddQuad("right", {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, green, n);
  if (block) {
    b.AddQuad("block_top", {0.3f, -0.2f, -0.2f}, {0, 0, 0.25f}, {0.25f, 0, 0}, white, n);
    b.AddQuad("block_front", {0.3f, -0.6f, 0.05f}, {0.25f, 0, 0}, {0, 0.4f, 0}, white, n);
    b.AddQuad("block_back", {0.3f, -0.6f, -0.45f}, {0, 0.4f, 0}, {0.25f, 0, 0}, white, n);
    b.AddQuad("block_left", {0.05f, -0.6f, -0.2f}, {0, 0, 0.25f}, {0, 0.4f, 0}, white, n);
    b.AddQuad("block_right", {0.55f, -0.6f, -0.2f}, {0, 0.4f, 0}, {0, 0, 0.25f}, white, n);
  }
  b.AddPointLight("lamp", {0.0f, 0.7f, 0.0f}, {1, 1, 1}, 8.0f);
  b.AddCamera("camera", {0.0f, 0.0f, 2.9f}, {0, 0, -1}, {0, 1, 0}, 0.8f);
  return b.ToJson();
}

// Quads per wall: 2 x 46^2 = 4,232 triangles, at least
// hierarchy::kMinProxyTriangles, so every wall's elements come from a level.
constexpr int kFine = 46;

constexpr uint32_t kSize = 32;

class ProxyElementsRender : public ::testing::TestWithParam<const char*> {};

TEST_P(ProxyElementsRender, FineFlatRoomThroughProxiesMatchesTheCoarseOriginal) {
  // 46 x 46 quads per wall (4,232 triangles: proxies simplify them back
  // towards the single quad) against one quad per wall. Both are then
  // subdivided to the scene-sized element limit; the elements differ only
  // in how the proxy triangulated each wall.
  const std::string solver = GetParam();
  auto coarse = testing::SharedEngine().LoadScene(testing::SceneFromBytes(FlatRoom(1)));
  auto fine = testing::SharedEngine().LoadScene(testing::SceneFromBytes(FlatRoom(kFine)));
  ASSERT_TRUE(coarse.ok()) << coarse.status();
  ASSERT_TRUE(fine.ok()) << fine.status();
  Engine& engine = testing::SharedEngine();
  const FloatImage original = testing::RenderExr(engine, coarse->id, solver, kSize, kSize);
  const FloatImage proxied = testing::RenderExr(engine, fine->id, solver, kSize, kSize);
  const FloatImage full =
      testing::RenderExr(engine, fine->id, solver, kSize, kSize, {{"full_detail", "true"}});
  EXPECT_EQ(proxied.non_finite(), 0u);
  const double error = testing::RelMse(proxied, original);
  const double error_full = testing::RelMse(full, original);
  testing::RecordMeasurement("relmse_proxy_vs_coarse", error);
  testing::RecordMeasurement("relmse_full_detail_vs_coarse", error_full);
  const glm::dvec3 mean_p = testing::ImageMean(proxied), mean_o = testing::ImageMean(original);
  testing::RecordMeasurement("mean_ratio", mean_p.g / mean_o.g);
  // Measured relMSE 9e-7 / 2e-12 (implicit_visibility / antiradiance;
  // full detail against the coarse room: 3.3e-4 / 9.7e-4), means within
  // 0.01 %.
  EXPECT_LT(error, 1e-3);
  EXPECT_NEAR(mean_p.g / mean_o.g, 1.0, 0.01);
  EXPECT_TRUE(engine.UnloadScene(coarse->id).ok());
  EXPECT_TRUE(engine.UnloadScene(fine->id).ok());
}

TEST_P(ProxyElementsRender, DisplayFromProxiesHasNoBlackPixels) {
  // The finely tessellated room with a block on the floor (silhouettes
  // against the walls and floor), each of its ten quads of 4,232 triangles
  // from a proxy level, at 48 px against full detail: every pixel finite,
  // none black (below 5 % of full detail) where full detail has light
  // (implicit_visibility's display draws the full mesh with the
  // irradiance transferred; antiradiance's splats reach over each leaf's
  // cell), and 8 x 8 blocks within 0.2 of full detail (relative to the
  // block's value plus 5 % of the image mean). Measured: darkest pixel 0.47
  // / 0.069 of full detail, worst block 0.019 / 0.029 (implicit_visibility
  // / antiradiance).
  const std::string solver = GetParam();
  auto loaded = testing::SharedEngine().LoadScene(testing::SceneFromBytes(FlatRoom(kFine, true)));
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  struct Loaded {
    std::string id;
    ~Loaded() { EXPECT_TRUE(testing::SharedEngine().UnloadScene(id).ok()); }
  } scene{loaded->id};
  Engine& engine = testing::SharedEngine();
  constexpr uint32_t kBox = 48;
  const FloatImage proxied = testing::RenderExr(engine, scene.id, solver, kBox, kBox);
  const FloatImage full =
      testing::RenderExr(engine, scene.id, solver, kBox, kBox, {{"full_detail", "true"}});
  ASSERT_EQ(proxied.width, int(kBox));
  ASSERT_EQ(full.width, int(kBox));
  EXPECT_EQ(proxied.non_finite(), 0u);
  const double mean = testing::ImageMean(full).g;
  int black = 0;
  double darkest = 1e30;
  for (int y = 0; y < int(kBox); ++y)
    for (int x = 0; x < int(kBox); ++x) {
      const glm::vec3 f = full.at(x, y), p = proxied.at(x, y);
      const float lf = f.r + f.g + f.b, lp = p.r + p.g + p.b;
      if (!(lf > 0.05f * float(mean))) continue;
      darkest = std::min(darkest, double(lp / lf));
      if (lp < 0.05f * lf) ++black;
    }
  EXPECT_EQ(black, 0);
  double worst = 0.0;
  for (int by = 0; by < int(kBox); by += 8)
    for (int bx = 0; bx < int(kBox); bx += 8) {
      const glm::vec3 f = full.mean(bx + 4, by + 4, 4), p = proxied.mean(bx + 4, by + 4, 4);
      worst = std::max(worst, double(glm::length(p - f) / (glm::length(f) + 0.05f * mean)));
    }
  testing::RecordMeasurement("darkest_pixel_ratio", darkest);
  testing::RecordMeasurement("worst_block_difference", worst);
  testing::RecordMeasurement("relmse_proxy_vs_full", testing::RelMse(proxied, full));
  EXPECT_LT(worst, 0.2);
}

INSTANTIATE_TEST_SUITE_P(VertexBased, ProxyElementsRender,
                         ::testing::Values("implicit_visibility", "antiradiance"));

}  // namespace proxy_elements_test
}  // namespace gistream
