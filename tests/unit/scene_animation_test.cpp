// The scene's animation clock and the deformation updates (SceneState,
// scene/validate_update): play, pause, seek, speed and looping of a glTF
// animation; morph weights and joint transforms as deformation changes;
// bad updates rejected naming the field.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "scene/state/scene_state.h"
#include "scene/state/validate_update.h"
#include "support/deforming_scene.h"

namespace gistream {
namespace scene_animation_test {

using testing::DeformingTube;

std::shared_ptr<const Scene> Tube() {
  return std::make_shared<const Scene>(testing::MakeDeformingTube());
}

AnimationUpdate Bend() {
  AnimationUpdate u;
  u.name = "bend";
  return u;
}

// The bend joint's angle about Z (the animation rotates it from 0 to
// kBendAngle over 2 s, LINEAR).
float BendAngle(const SceneState& state) {
  return glm::angle(state.nodes()[DeformingTube::kBendJoint].rotation);
}

TEST(SceneAnimation, NothingMovesUntilPlayedOrSeeked) {
  SceneState state(Tube());
  EXPECT_EQ(state.Advance(1.0), kChangeNone);
  AnimationUpdate speed = Bend();
  speed.speed = 2.0f;
  EXPECT_EQ(state.Apply(speed), kChangeNone);  // the rate alone moves nothing
  EXPECT_EQ(state.Advance(1.0), kChangeNone);
  EXPECT_EQ(BendAngle(state), 0.0f);
}

TEST(SceneAnimation, PlayingAdvancesWithTheClockTimesSpeed) {
  SceneState state(Tube());
  AnimationUpdate play = Bend();
  play.playing = true;
  play.speed = 0.5f;
  state.Apply(play);
  const uint64_t before = state.version();
  EXPECT_EQ(state.Advance(1.0), kChangeDeformation);  // 0.5 s of the keys
  EXPECT_GT(state.version(), before);
  EXPECT_NEAR(state.animations()[0].time, 0.5, 1e-9);
  // LINEAR slerp: a quarter of the way (tolerance: float slerp rounding).
  EXPECT_NEAR(BendAngle(state), 0.25f * DeformingTube::kBendAngle, 1e-5f);
  EXPECT_EQ(state.ChangesSince(before) & kChangeDeformation, kChangeDeformation);
}

TEST(SceneAnimation, LoopsWrapAndOneShotsStopAtTheEnd) {
  SceneState state(Tube());
  AnimationUpdate play = Bend();
  play.playing = true;
  state.Apply(play);
  state.Advance(2.5);  // loops by default: 2.5 s is 0.5 s into [0, 2)
  EXPECT_NEAR(state.animations()[0].time, 0.5, 1e-9);
  AnimationUpdate once = Bend();
  once.loop = false;
  state.Apply(once);
  state.Advance(5.0);
  EXPECT_NEAR(state.animations()[0].time, 2.0, 1e-9);
  EXPECT_NEAR(BendAngle(state), DeformingTube::kBendAngle, 1e-5f);
  EXPECT_EQ(state.Advance(1.0), kChangeNone);  // held at the end: no new version
  AnimationUpdate backwards = Bend();
  backwards.speed = -1.0f;
  backwards.loop = true;
  state.Apply(backwards);
  state.Advance(2.5);  // 2.0 - 2.5 wraps to 1.5
  EXPECT_NEAR(state.animations()[0].time, 1.5, 1e-9);
}

TEST(SceneAnimation, PauseHoldsAndSeekIsExact) {
  SceneState state(Tube());
  AnimationUpdate play = Bend();
  play.playing = true;
  state.Apply(play);
  AnimationUpdate pause = Bend();
  pause.playing = false;
  pause.time = 1.0f;
  EXPECT_EQ(state.Apply(pause), kChangeDeformation);
  EXPECT_EQ(state.Advance(0.3), kChangeNone);
  EXPECT_NEAR(state.animations()[0].time, 1.0, 1e-9);
  EXPECT_NEAR(BendAngle(state), 0.5f * DeformingTube::kBendAngle, 1e-5f);
}

TEST(SceneAnimation, JointsAndWeightsAreDeformationChanges) {
  SceneState state(Tube());
  NodeTransformUpdate joint;
  joint.node = DeformingTube::kBendJoint;
  joint.translation = glm::vec3(0.0f, 1.0f, 0.0f);
  joint.rotation = glm::angleAxis(0.5f, glm::vec3(0.0f, 0.0f, 1.0f));
  EXPECT_EQ(state.Apply(joint), kChangeDeformation);
  const Primitive& posed = state.NodeMesh(DeformingTube::kTubeNode).primitives[0];
  const Primitive& rest = state.scene().meshes[0].primitives[0];
  EXPECT_NE(posed.positions.back(), rest.positions.back());    // the top ring bent
  EXPECT_EQ(posed.positions.front(), rest.positions.front());  // the bottom one did not
  EXPECT_EQ(state.Apply(MorphWeightsUpdate{DeformingTube::kTubeNode, {1.0f}}), kChangeDeformation);
  EXPECT_TRUE(state.Deforms(DeformingTube::kTubeNode));
  EXPECT_FALSE(state.Deforms(DeformingTube::kRootJoint));
}

TEST(SceneAnimation, CheckApplyLeavesTheStateAsItWas) {
  SceneState state(Tube());
  NodeTransformUpdate joint;
  joint.node = DeformingTube::kBendJoint;
  joint.rotation = glm::angleAxis(0.5f, glm::vec3(0.0f, 0.0f, 1.0f));
  const std::vector<glm::vec3> before =
      state.NodeMesh(DeformingTube::kTubeNode).primitives[0].positions;
  EXPECT_TRUE(state.CheckApply(joint).ok());
  EXPECT_EQ(state.NodeMesh(DeformingTube::kTubeNode).primitives[0].positions, before);
}

absl::Status Validate(const Scene& scene, Change change) {
  return ValidateUpdate(scene, Update{1, std::move(change)}, 4096, 4096);
}

void ExpectRejected(const Scene& scene, Change change, const std::string& field) {
  const absl::Status status = Validate(scene, std::move(change));
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_NE(status.message().find(field), std::string::npos) << status;
}

TEST(SceneAnimation, BadAnimationUpdatesNameTheField) {
  const auto scene = Tube();
  AnimationUpdate ok = Bend();
  ok.playing = true;
  EXPECT_TRUE(Validate(*scene, ok).ok());
  AnimationUpdate unknown = ok;
  unknown.name = "walk";
  ExpectRejected(*scene, unknown, "update.animation.name: 'walk'");
  AnimationUpdate both = ok;
  both.animation = 0;
  ExpectRejected(*scene, both, "update.animation: give exactly one");
  AnimationUpdate index;
  index.animation = 3;
  index.playing = true;
  ExpectRejected(*scene, index, "update.animation.animation: 3 is out of range");
  AnimationUpdate empty = Bend();
  ExpectRejected(*scene, empty, "update.animation: sets none");
  AnimationUpdate nan = Bend();
  nan.time = std::numeric_limits<float>::quiet_NaN();
  ExpectRejected(*scene, nan, "update.animation.time: nan is not finite");
  AnimationUpdate fast = Bend();
  fast.speed = 1e4f;
  ExpectRejected(*scene, fast, "update.animation.speed");
}

TEST(SceneAnimation, BadMorphWeightsNameTheField) {
  const auto scene = Tube();
  EXPECT_TRUE(Validate(*scene, MorphWeightsUpdate{DeformingTube::kTubeNode, {0.5f}}).ok());
  ExpectRejected(*scene, MorphWeightsUpdate{DeformingTube::kTubeNode, {0.5f, 0.5f}},
                 "update.morph_weights.weights: 2 weights for 1 morph targets");
  ExpectRejected(*scene, MorphWeightsUpdate{DeformingTube::kRootJoint, {0.5f}},
                 "update.morph_weights.node: 1 draws no mesh with morph targets");
  ExpectRejected(*scene, MorphWeightsUpdate{9, {0.5f}}, "update.morph_weights.node: 9");
  ExpectRejected(
      *scene,
      MorphWeightsUpdate{DeformingTube::kTubeNode, {std::numeric_limits<float>::infinity()}},
      "update.morph_weights.weights[0]: inf is not finite");
  ExpectRejected(*scene, MorphWeightsUpdate{DeformingTube::kTubeNode, {500.0f}},
                 "update.morph_weights.weights[0]: 500 exceeds");
}

}  // namespace scene_animation_test
}  // namespace gistream
