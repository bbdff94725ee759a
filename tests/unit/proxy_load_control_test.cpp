// A scene's proxies within a load's time budget and stop (issue 19,
// scene/gltf/load_control.h): a passed deadline keeps what is done (levels
// first, trees dropped) and says so; a stop ends the build with its code,
// naming the primitive and stage.
#include <gtest/gtest.h>

#include <string>

#include "scene/gltf/load_control.h"
#include "scene/proxies/proxy_clusters.h"
#include "scene/proxies/proxy_levels.h"
#include "support/test_meshes.h"

namespace gistream {
namespace proxy_load_control_test {

// A floor of 72 x 72 quads (10,368 triangles: tree-sized) and a sphere of
// 24 x 48 quads (2,304: levels only), one mesh each.
Scene TwoMeshScene() {
  Scene scene;
  scene.meshes.push_back({"floor", {testing::FloorGrid(72)}});
  scene.meshes.push_back({"sphere", {testing::UvSphere(glm::vec3(0.0f), 1.0f, 24, 48)}});
  return scene;
}

TEST(ProxyLoadControl, WithoutLimitsEqualsThePlainBuild) {
  Scene plain = TwoMeshScene(), controlled = TwoMeshScene();
  BuildSceneProxies(&plain);
  ProxyReport report;
  ASSERT_TRUE(BuildSceneProxies(&controlled, LoadControl{}, &report).ok());
  EXPECT_EQ(report.primitives_with_levels, 2u);
  EXPECT_EQ(report.primitives_with_trees, 1u);
  EXPECT_EQ(report.levels_skipped + report.trees_skipped, 0u);
  for (size_t m = 0; m < 2; ++m) {
    const Primitive &a = plain.meshes[m].primitives[0], &b = controlled.meshes[m].primitives[0];
    ASSERT_EQ(a.proxies.size(), b.proxies.size());
    for (size_t l = 0; l < a.proxies.size(); ++l) {
      EXPECT_EQ(a.proxies[l].indices, b.proxies[l].indices);
      EXPECT_EQ(a.proxies[l].error, b.proxies[l].error);
    }
    ASSERT_EQ(a.clusters.size(), b.clusters.size());
    for (size_t n = 0; n < a.clusters.size(); ++n) {
      EXPECT_EQ(a.clusters[n].level.indices, b.clusters[n].level.indices);
      EXPECT_EQ(a.clusters[n].level.error, b.clusters[n].level.error);
    }
  }
  EXPECT_FALSE(controlled.meshes[0].primitives[0].clusters.empty());
}

TEST(ProxyLoadControl, PassedDeadlineBuildsNothingAndSaysSo) {
  Scene scene = TwoMeshScene();
  LoadControl control;
  control.optional_deadline = LoadControl::Clock::now();
  ProxyReport report;
  ASSERT_TRUE(BuildSceneProxies(&scene, control, &report).ok());
  EXPECT_EQ(report.primitives_with_levels, 0u);
  EXPECT_EQ(report.levels_skipped, 2u);
  EXPECT_EQ(report.trees_skipped, 1u);  // only the floor is tree-sized
  for (const Mesh& mesh : scene.meshes) {
    EXPECT_TRUE(mesh.primitives[0].proxies.empty());
    EXPECT_TRUE(mesh.primitives[0].clusters.empty());
  }
}

// The deadline passes while the floor's tree is half built (made to pass
// from inside the stop poll, so the test needs no clock): the levels stay,
// the tree is dropped whole (no partial tree is ever drawn).
TEST(ProxyLoadControl, DeadlineDuringTheTreesKeepsTheLevels) {
  Scene scene = TwoMeshScene();
  Scene full = TwoMeshScene();
  BuildSceneProxies(&full);
  // The polls come from the floor's and the sphere's levels, then from
  // the tree's nodes: count the levels' first.
  int polls_at_trees = 0;
  LoadControl counting;
  counting.stop = [&]() {
    ++polls_at_trees;
    return absl::OkStatus();
  };
  for (const Mesh& mesh : scene.meshes) {
    bool cut = false;
    ASSERT_TRUE(BuildProxyLevels(mesh.primitives[0], ProxySettings{}, counting, &cut).ok());
  }
  LoadControl control;
  int polls = 0;
  control.stop = [&]() {
    if (++polls == polls_at_trees + 3) control.optional_deadline = LoadControl::Clock::now();
    return absl::OkStatus();
  };
  ProxyReport report;
  ASSERT_TRUE(BuildSceneProxies(&scene, control, &report).ok());
  EXPECT_EQ(report.levels_skipped, 0u);
  EXPECT_EQ(report.trees_skipped, 1u);
  EXPECT_EQ(report.primitives_with_trees, 0u);
  EXPECT_EQ(report.primitives_with_levels, 2u);
  EXPECT_TRUE(scene.meshes[0].primitives[0].clusters.empty());
  ASSERT_EQ(scene.meshes[0].primitives[0].proxies.size(),
            full.meshes[0].primitives[0].proxies.size());
  for (size_t l = 0; l < full.meshes[0].primitives[0].proxies.size(); ++l) {
    EXPECT_EQ(scene.meshes[0].primitives[0].proxies[l].error,
              full.meshes[0].primitives[0].proxies[l].error);
  }
}

TEST(ProxyLoadControl, StopEndsTheBuildNamingPrimitiveAndStage) {
  for (const bool deadline : {false, true}) {
    Scene scene = TwoMeshScene();
    LoadControl control;
    int polls = 0;
    // Past the floor's levels (its first few polls): inside a tree or the
    // sphere's levels.
    control.stop = [&]() -> absl::Status {
      if (++polls < 12) return absl::OkStatus();
      return deadline ? absl::DeadlineExceededError("the client's deadline passed")
                      : absl::CancelledError("the client cancelled the call");
    };
    ProxyReport report;
    const absl::Status status = BuildSceneProxies(&scene, control, &report);
    EXPECT_EQ(status.code(),
              deadline ? absl::StatusCode::kDeadlineExceeded : absl::StatusCode::kCancelled);
    const std::string message(status.message());
    EXPECT_NE(message.find("].primitives[0]: proxy "), std::string::npos) << message;
    EXPECT_NE(message.find(deadline ? "deadline passed" : "cancelled"), std::string::npos)
        << message;
  }
}

}  // namespace proxy_load_control_test
}  // namespace gistream
