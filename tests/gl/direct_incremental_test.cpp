// Direct light redraws only the shadow maps a change made stale: an
// emission-strength or intensity change redraws none and scales the image
// exactly; moving one light redraws its map alone; moving geometry redraws
// every map. The image after an incremental update equals a fresh render.
#include <set>

#include <gtest/gtest.h>

#include "support/frame_queue.h"
#include "support/render_helpers.h"

namespace gistream {
namespace direct_incremental_test {

using testing::BundledCopy;
using testing::FloatImage;
using testing::FrameStat;

struct Rendered {
  FloatImage image;
  EncodedFrame frame;
};

// `budget_ms`: the frame budget; 10 s draws every stale map in one slice.
Rendered RenderDirect(const std::string& scene, std::vector<Update> updates = {},
                      double budget_ms = 10'000.0) {
  RenderRequest request = testing::SolverRequest(
      scene, "direct", {{"area_samples", "16"}, {"shadow_res", "64"}}, 32, std::move(updates));
  request.frame_budget_ms = budget_ms;
  Rendered out;
  out.image = testing::RenderRequestExr(request, &out.frame);
  return out;
}

NodeTransformUpdate MoveTallBlock() {
  NodeTransformUpdate move;
  move.node = 6;  // cornell_box's tall_block
  move.translation = glm::vec3(0.20f, 0.0f, 0.30f);
  return move;
}

Update Emission(float strength, uint64_t seq = 1) {
  MaterialUpdate m;
  m.material = 3;  // cornell_box's "light" material
  m.emissive_strength = strength;
  return {seq, m};
}

TEST(DirectIncremental, EmissionStrengthRedrawsNoShadowMapAndScalesTheImage) {
  const BundledCopy scene("cornell_box.gltf");
  const Rendered first = RenderDirect(scene.id(), {Emission(10.0f)});
  EXPECT_EQ(FrameStat(first.frame, "shadow_maps_redrawn"), 16.0);  // every area sample's cube
  const Rendered doubled = RenderDirect(scene.id(), {Emission(20.0f)});
  EXPECT_EQ(FrameStat(doubled.frame, "shadow_maps_redrawn"), 0.0);
  // Direct light is linear in the emission: every pixel doubles (float
  // rounding only), the emitter's own pixels included.
  ASSERT_EQ(first.image.rgba.size(), doubled.image.rgba.size());
  size_t lit = 0;
  for (size_t i = 0; i < first.image.rgba.size(); i += 4) {
    for (int c = 0; c < 3; ++c) {
      const float a = first.image.rgba[i + size_t(c)], b = doubled.image.rgba[i + size_t(c)];
      ASSERT_NEAR(b, 2.0f * a, 1e-4f * std::max(1.0f, a)) << "pixel " << i / 4;
      lit += a > 0.0f ? 1 : 0;
    }
  }
  EXPECT_GT(lit, first.image.rgba.size() / 8);  // the test looked at a lit image
}

TEST(DirectIncremental, MovingGeometryRedrawsEveryMapAndMatchesAFreshRender) {
  const BundledCopy incremental("cornell_box.gltf"), fresh("cornell_box.gltf");
  RenderDirect(incremental.id());
  const NodeTransformUpdate move = MoveTallBlock();
  const Rendered moved = RenderDirect(incremental.id(), {{1, move}});
  EXPECT_EQ(FrameStat(moved.frame, "shadow_maps_redrawn"), 16.0);
  // An emission change afterwards keeps the moved block's shadows...
  const Rendered after = RenderDirect(incremental.id(), {Emission(17.0f, 2)});
  EXPECT_EQ(FrameStat(after.frame, "shadow_maps_redrawn"), 0.0);
  // ... and gives what a fresh solver renders for the same state.
  const Rendered reference = RenderDirect(fresh.id(), {{1, move}, Emission(17.0f, 2)});
  testing::ExpectSameImage(after.image, reference.image);
}

TEST(DirectIncremental, ASlicedRedrawAfterAMoveEqualsAFreshRender) {
  // 0.01 ms: after the first, every slice draws one map into the second
  // set; the frame (a Render waits for it) shows the new set only whole.
  const BundledCopy incremental("cornell_box.gltf"), fresh("cornell_box.gltf");
  RenderDirect(incremental.id());
  const NodeTransformUpdate move = MoveTallBlock();
  const Rendered sliced = RenderDirect(incremental.id(), {{1, move}}, 0.01);
  EXPECT_EQ(FrameStat(sliced.frame, "shadow_maps_pending"), 0.0);
  EXPECT_LT(FrameStat(sliced.frame, "shadow_maps_redrawn"), 16.0);  // the last of several slices
  const Rendered reference = RenderDirect(fresh.id(), {{1, move}});
  testing::ExpectSameImage(sliced.image, reference.image);
}

TEST(DirectIncremental, AChangeWhileASlicedRedrawRunsStillEndsConsistent) {
  // A stream with a tiny budget: the move's maps are drawn over many
  // frames; an emission change arrives meanwhile. The frames keep coming,
  // and once nothing is pending the image is what a fresh solver renders
  // for the final state (no map of the old geometry survives).
  const BundledCopy scene("cornell_box.gltf"), fresh("cornell_box.gltf");
  SessionConfig config = testing::ExrStreamConfig(
      scene.id(), "direct", {{"area_samples", "16"}, {"shadow_res", "64"}}, 32);
  config.frame_budget_ms = 0.01;
  config.encoding.send_unchanged = true;  // the last frame's picture, even if the same
  auto sink = std::make_shared<testing::FrameQueue>();
  auto opened = testing::SharedEngine().OpenSession(config, sink);
  ASSERT_TRUE(opened.ok()) << opened.status();
  ASSERT_NE(sink->Next(), nullptr);
  const NodeTransformUpdate move = MoveTallBlock();
  ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, {1, move}).ok());
  // A frame that shows the move with its maps still pending, then the change.
  auto stat = [](const EncodedFrame& f, const std::string& name) {
    for (const auto& [k, v] : f.stats) {
      if (k == name) return v;
    }
    return -1.0;
  };
  ASSERT_NE(sink->WaitFor([&](const EncodedFrame& f) {
    return f.last_update_seq >= 1 && stat(f, "shadow_maps_pending") == 1.0;
  }),
            nullptr);
  ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, Emission(17.0f, 2)).ok());
  auto done = sink->WaitFor([&](const EncodedFrame& f) {
    return f.last_update_seq >= 2 && stat(f, "shadow_maps_pending") == 0.0;
  });
  testing::SharedEngine().CloseSession(opened->id);
  ASSERT_NE(done, nullptr);
  const Rendered reference = RenderDirect(fresh.id(), {{1, move}, Emission(17.0f, 2)});
  testing::ExpectSameImage(testing::DecodeExr(*done), reference.image);
}

TEST(DirectIncremental, UnderAMoveEveryFrameTheShadowsStillFollow) {
  // One map a frame (0.01 ms), 16 maps a set, and the block moved on every
  // frame for 64 frames: each set drawn is shown, the next one (of the
  // newest state) after it (or, once per set shown, instead of it on a
  // frame without a change). A change that replaced the set being drawn
  // would show none until the moves stop (measured 0 here before).
  const BundledCopy scene("cornell_box.gltf");
  SessionConfig config = testing::ExrStreamConfig(
      scene.id(), "direct", {{"area_samples", "16"}, {"shadow_res", "64"}}, 32);
  config.frame_budget_ms = 0.01;
  auto sink = std::make_shared<testing::FrameQueue>();
  auto opened = testing::SharedEngine().OpenSession(config, sink);
  ASSERT_TRUE(opened.ok()) << opened.status();
  std::shared_ptr<const EncodedFrame> frame = sink->Next();
  ASSERT_NE(frame, nullptr);
  const double shown_before = FrameStat(*frame, "shadow_sets_shown");
  NodeTransformUpdate move = MoveTallBlock();
  for (uint64_t seq = 1; seq <= 64; ++seq) {
    move.translation.x = 0.15f + 0.002f * float(seq);
    ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, {seq, move}).ok());
    frame = sink->WaitFor([&](const EncodedFrame& f) { return f.last_update_seq >= seq; });
    ASSERT_NE(frame, nullptr);
  }
  testing::SharedEngine().CloseSession(opened->id);
  // 64 frames at one map each: two sets at least (the first may have had
  // maps drawn before the moves began, and sets may be dropped once each).
  EXPECT_GE(FrameStat(*frame, "shadow_sets_shown") - shown_before, 2.0);
}

TEST(DirectIncremental, AQueuedSetOfANewLayoutEndsConsistent) {
  // The lamp off (no area sample, no cube), on again in slices (16 cubes
  // into the second set) and, while that set is drawn, the block moved:
  // the move's set waits behind it and is drawn into the maps the first
  // one hid, which were sized for none. Once nothing is pending the
  // picture is a fresh solver's of the final state.
  const BundledCopy scene("cornell_box.gltf"), fresh("cornell_box.gltf");
  SessionConfig config = testing::ExrStreamConfig(
      scene.id(), "direct", {{"area_samples", "16"}, {"shadow_res", "64"}}, 32);
  config.frame_budget_ms = 0.01;
  config.encoding.send_unchanged = true;
  auto sink = std::make_shared<testing::FrameQueue>();
  auto opened = testing::SharedEngine().OpenSession(config, sink);
  ASSERT_TRUE(opened.ok()) << opened.status();
  ASSERT_NE(sink->Next(), nullptr);
  const auto shows = [&](uint64_t seq, double pending) {
    return sink->WaitFor([&](const EncodedFrame& f) {
      return f.last_update_seq >= seq && FrameStat(f, "shadow_maps_pending") == pending;
    });
  };
  ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, Emission(0.0f, 1)).ok());
  ASSERT_NE(shows(1, 0.0), nullptr);
  ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, Emission(10.0f, 2)).ok());
  // More than half of its 16 maps drawn (one a frame), so that the move's
  // set waits behind it rather than replacing it.
  std::set<uint64_t> drawing;  // frames (WaitFor looks at every frame again each time)
  ASSERT_NE(sink->WaitFor([&](const EncodedFrame& f) {
    if (f.last_update_seq >= 2 && FrameStat(f, "shadow_maps_pending") == 1.0)
      drawing.insert(f.frame_number);
    return drawing.size() >= 10;
  }),
            nullptr);
  const NodeTransformUpdate move = MoveTallBlock();
  ASSERT_TRUE(testing::SharedEngine().PushUpdate(opened->id, {3, move}).ok());
  std::shared_ptr<const EncodedFrame> done = shows(3, 0.0);
  testing::SharedEngine().CloseSession(opened->id);
  ASSERT_NE(done, nullptr);
  const Rendered reference =
      RenderDirect(fresh.id(), {Emission(0.0f, 1), Emission(10.0f, 2), {3, move}});
  testing::ExpectSameImage(testing::DecodeExr(*done), reference.image);
}

TEST(DirectIncremental, MovingOnePunctualLightRedrawsItsMapAlone) {
  // dynamic_block: light 0 is a point light (a cube), light 1 the sun (a
  // directional map); no emitters.
  const BundledCopy scene("dynamic_block.gltf");
  const Rendered first = RenderDirect(scene.id());
  EXPECT_EQ(FrameStat(first.frame, "shadow_maps_redrawn"), 2.0);
  LightUpdate dim;
  dim.light = 0;
  dim.intensity = 3.0f;
  EXPECT_EQ(FrameStat(RenderDirect(scene.id(), {{1, dim}}).frame, "shadow_maps_redrawn"), 0.0);
  LightUpdate move;
  move.light = 0;
  move.position = glm::vec3(0.3f, 2.0f, 0.4f);
  EXPECT_EQ(FrameStat(RenderDirect(scene.id(), {{2, move}}).frame, "shadow_maps_redrawn"), 1.0);
  LightUpdate sun;
  sun.light = 1;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  EXPECT_EQ(FrameStat(RenderDirect(scene.id(), {{3, sun}}).frame, "shadow_maps_redrawn"), 1.0);
}

}  // namespace direct_incremental_test
}  // namespace gistream
