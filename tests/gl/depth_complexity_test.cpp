// DepthComplexity (solvers/work_estimate.h): 2 A / S, the mean number of
// surfaces a line through the scene's bounds crosses (Cauchy-Crofton),
// which scales implicit_visibility's linking estimate. Closed forms: a
// cube's six faces inside its own bounds give exactly 2, a half-size cube
// nested inside adds 2 (1/4 of the area) / 1 = 0.5, one plane is 1.
#include <gtest/gtest.h>

#include <cstdint>
#include <span>
#include <string>

#include "scene/gltf/gltf_import.h"
#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"
#include "solvers/work_estimate.h"
#include "support/gl_context.h"
#include "support/gltf_builder.h"

namespace gistream {
namespace depth_complexity_test {

// The six faces of a cube of half-size h centred at the origin.
void AddCube(testing::GltfBuilder& b, float h, int material) {
  b.AddQuad("x+", {h, 0, 0}, {0, h, 0}, {0, 0, h}, material);
  b.AddQuad("x-", {-h, 0, 0}, {0, 0, h}, {0, h, 0}, material);
  b.AddQuad("y+", {0, h, 0}, {0, 0, h}, {h, 0, 0}, material);
  b.AddQuad("y-", {0, -h, 0}, {h, 0, 0}, {0, 0, h}, material);
  b.AddQuad("z+", {0, 0, h}, {h, 0, 0}, {0, h, 0}, material);
  b.AddQuad("z-", {0, 0, -h}, {0, h, 0}, {h, 0, 0}, material);
}

double DepthOf(const testing::GltfBuilder& b) {
  const std::string json = b.ToJson();
  auto scene = ImportGltf(
      std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()), {});
  EXPECT_TRUE(scene.ok()) << scene.status();
  if (!scene.ok()) return -1.0;
  SceneState state(std::make_shared<const Scene>(*std::move(scene)));
  auto gpu = GpuScene::Upload(state);
  EXPECT_TRUE(gpu.ok()) << gpu.status();
  return gpu.ok() ? DepthComplexity(state, **gpu) : -1.0;
}

TEST(DepthComplexity, IsTwiceTheAreaOverTheBoundsSurface) {
  const auto context = testing::CurrentGlContext();
  ASSERT_TRUE(context);
  for (float h : {1e-3f, 1.0f, 1e3f}) {
    SCOPED_TRACE(h);
    testing::GltfBuilder room;
    AddCube(room, h, room.AddMaterial("white", {0.8f, 0.8f, 0.8f}));
    EXPECT_NEAR(DepthOf(room), 2.0, 1e-4);
    testing::GltfBuilder nested;
    const int white = nested.AddMaterial("white", {0.8f, 0.8f, 0.8f});
    AddCube(nested, h, white);
    AddCube(nested, 0.5f * h, white);
    EXPECT_NEAR(DepthOf(nested), 2.5, 1e-4);
  }
  testing::GltfBuilder plane;
  plane.AddQuad("floor", {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, plane.AddMaterial("w", {1, 1, 1}), 4);
  EXPECT_NEAR(DepthOf(plane), 1.0, 1e-6);
  context->ReleaseCurrent();
}

}  // namespace depth_complexity_test
}  // namespace gistream
