// A scene load's time is bounded (issue 19, scene/gltf/load_control.h): past
// EngineOptions::max_load_time (gistreamd --max-load-seconds) the proxies
// stop and the scene loads and renders without them, saying so; a load
// whose caller stops (client gone or past its deadline) answers that code
// naming the stage and keeps nothing.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "reliability/reliability_fixture.h"
#include "support/gltf_builder.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace load_budget_test {

// QuadScene with its floor as 72 x 72 quads (10,368 triangles): large
// enough for proxy levels and a cluster tree.
std::string FineFloorScene() {
  testing::GltfBuilder b;
  const int white = b.AddMaterial("white", {0.8f, 0.8f, 0.8f});
  const int lamp = b.AddMaterial("lamp", {0, 0, 0}, {1, 1, 1}, 5.0f);
  b.AddQuad("floor", {0, 0, 0}, {1, 0, 0}, {0, 0, -1}, white, 72);
  b.AddQuad("lamp", {0, 1.5f, 0}, {0.2f, 0, 0}, {0, 0, 0.2f}, lamp);
  b.AddPointLight("bulb", {0, 1, 0}, {1, 1, 1}, 5.0f);
  b.AddCamera("cam", {0, 2, 2}, {0, -0.70710678f, -0.70710678f}, {0, 1, 0}, 0.8f);
  return b.ToJson();
}

TEST(LoadBudget, TinyBudgetLoadsAndRendersWithoutTheTrees) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  options.max_load_time = std::chrono::milliseconds(0);
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();  // GL tests never skip
  Engine& e = **engine;
  auto cut = e.LoadScene(testing::SceneFromBytes(FineFloorScene()));
  ASSERT_TRUE(cut.ok()) << cut.status();
  EXPECT_EQ(cut->proxy_trees_skipped, 1u);  // the floor's
  EXPECT_GE(cut->proxy_levels_skipped, 1u);
  EXPECT_EQ(cut->triangle_count, 10'368u + 2u);

  // The shared engine has the default budget: the same scene with its tree.
  auto built = E().LoadScene(testing::SceneFromBytes(FineFloorScene()));
  ASSERT_TRUE(built.ok()) << built.status();
  EXPECT_EQ(built->proxy_trees_skipped, 0u);
  EXPECT_EQ(built->proxy_levels_skipped, 0u);

  auto frame = e.Render(Request(cut->id, "direct"));
  ASSERT_TRUE(frame.ok()) << frame.status();
  const testing::FloatImage without = testing::DecodeExr(*frame);
  auto reference = E().Render(Request(built->id, "direct"));
  ASSERT_TRUE(reference.ok()) << reference.status();
  const testing::FloatImage with = testing::DecodeExr(*reference);
  EXPECT_EQ(without.non_finite(), 0u);
  const double mean = testing::ImageMean(without).x, ref = testing::ImageMean(with).x;
  EXPECT_GT(mean, 0.0) << "the lit floor renders black";
  // The floor is flat: its proxies are the same surface, so the image with
  // the full mesh matches the one with the tree (shadow-map depth only).
  EXPECT_NEAR(mean, ref, 0.01 * ref);
  ASSERT_TRUE(E().UnloadScene(built->id).ok());
  e.Shutdown();
}

TEST(LoadBudget, StoppedLoadAnswersItsCodeNamingTheStageAndKeepsNothing) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();
  Engine& e = **engine;
  const uint64_t memory_before = e.stats().memory_used_bytes;
  const uint32_t scenes_before = e.stats().scenes;

  // Stopped at the first poll (after parsing), and in the proxies.
  struct Case {
    int at_poll;
    absl::Status stop;
    absl::StatusCode code;
    std::string stage;
  };
  const Case cases[] = {
      {1, absl::DeadlineExceededError("the client's deadline passed"),
       absl::StatusCode::kDeadlineExceeded, "import: after parsing: the client's deadline passed"},
      {1, absl::CancelledError("the client cancelled the call"), absl::StatusCode::kCancelled,
       "import: after parsing: the client cancelled"},
      {4, absl::CancelledError("the client cancelled the call"), absl::StatusCode::kCancelled,
       "meshes[0].primitives[0]: proxy levels: the client cancelled"},
  };
  for (const Case& c : cases) {
    SceneSource source = testing::SceneFromBytes(FineFloorScene());
    int polls = 0;
    source.stop = [&]() { return ++polls >= c.at_poll ? c.stop : absl::OkStatus(); };
    const auto loaded = e.LoadScene(source);
    EXPECT_EQ(loaded.status().code(), c.code) << loaded.status();
    EXPECT_NE(std::string(loaded.status().message()).find(c.stage), std::string::npos)
        << loaded.status();
    EXPECT_EQ(e.stats().memory_used_bytes, memory_before) << "a stopped load holds nothing";
    EXPECT_EQ(e.stats().scenes, scenes_before);
  }
  // The engine still loads and renders it.
  auto info = e.LoadScene(testing::SceneFromBytes(FineFloorScene()));
  ASSERT_TRUE(info.ok()) << info.status();
  auto frame = e.Render(Request(info->id, "direct"));
  ASSERT_TRUE(frame.ok()) << frame.status();
  EXPECT_EQ(testing::DecodeExr(*frame).non_finite(), 0u);
  e.Shutdown();
}

}  // namespace load_budget_test
}  // namespace gistream::reliability
