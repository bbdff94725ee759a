// Named scenes: a named scene loaded twice by one tenant is one shared
// scene, also when the loads come at the same moment (issue 30: 16
// concurrent loads made 4 scenes); a load with private_copy (issue 29,
// isolated measurements) gets a scene of its own that no other load finds,
// so a change another client makes to the shared one (a viewer's slider)
// does not reach it.
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "reliability/reliability_fixture.h"

namespace gistream::reliability {
namespace named_scene_test {

RenderRequest Png(const std::string& scene, std::vector<Update> updates = {}) {
  RenderRequest r = Request(scene, "direct", std::move(updates));
  r.encoding.format = ImageFormat::kPng;  // (EXR headers carry the time of writing)
  return r;
}

SceneSource Named(bool private_copy) {
  SceneSource s;
  s.name = "quad";
  s.private_copy = private_copy;
  return s;
}

TEST(NamedScene, APrivateCopyIsNotShared) {
  auto shared = E().LoadScene(Named(false));
  auto again = E().LoadScene(Named(false));
  auto own = E().LoadScene(Named(true));
  auto own_too = E().LoadScene(Named(true));
  ASSERT_TRUE(shared.ok() && again.ok() && own.ok() && own_too.ok()) << own.status();
  EXPECT_EQ(shared->id, again->id) << "a named scene is shared by its loads";
  EXPECT_NE(own->id, shared->id);
  EXPECT_NE(own_too->id, own->id) << "each private copy is its own";
  // Another client dims the shared scene's emitter: the private copy's
  // picture does not change.
  const auto before = E().Render(Png(own->id));
  ASSERT_TRUE(before.ok()) << before.status();
  MaterialUpdate dim;
  dim.material = 1;
  dim.emissive_strength = 0.01f;
  const auto dimmed = E().Render(Png(shared->id, {U(dim)}));
  ASSERT_TRUE(dimmed.ok()) << dimmed.status();
  EXPECT_NE(dimmed->image, before->image) << "the dimmer changed nothing: the test proves nothing";
  const auto after = E().Render(Png(own->id));
  ASSERT_TRUE(after.ok()) << after.status();
  EXPECT_EQ(after->scene_version, before->scene_version);
  EXPECT_EQ(after->image, before->image);
  for (const auto& id : {shared->id, own->id, own_too->id}) EXPECT_TRUE(E().UnloadScene(id).ok());
  EXPECT_TRUE(E().UnloadScene(again->id).ok());
}

TEST(NamedScene, ConcurrentLoadsOfOneNameMakeOneScene) {
  constexpr int kLoads = 12;
  std::vector<absl::StatusOr<SceneInfo>> loaded(kLoads, absl::UnknownError("not run"));
  std::vector<std::thread> threads;
  for (int i = 0; i < kLoads; ++i) {
    threads.emplace_back([&loaded, i] { loaded[size_t(i)] = E().LoadScene(Named(false)); });
  }
  for (std::thread& t : threads) t.join();
  for (const auto& l : loaded) ASSERT_TRUE(l.ok()) << l.status();
  for (const auto& l : loaded) EXPECT_EQ(l->id, loaded[0]->id);
  // One scene, held by kLoads loads: each unload drops one.
  size_t scenes = 0;
  for (const SceneId& id : E().stats().scene_ids) scenes += id == loaded[0]->id ? 1 : 0;
  EXPECT_EQ(scenes, 1u);
  for (int i = 0; i < kLoads; ++i) EXPECT_TRUE(E().UnloadScene(loaded[0]->id).ok()) << i;
  EXPECT_FALSE(E().UnloadScene(loaded[0]->id).ok()) << "unloaded more often than loaded";
}

}  // namespace named_scene_test
}  // namespace gistream::reliability
