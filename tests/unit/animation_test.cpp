// Animation sampling (scene/state/animation.h) against hand-computed values for
// LINEAR, STEP and CUBICSPLINE (glTF 2.0 Appendix C), and the import of
// glTF animations with invalid ones rejected naming their JSON path.
// Tolerance: 1e-5 absolute on every sampled component (float arithmetic on
// values of order 1).
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/quaternion.hpp>

#include "gltf_test_util.h"
#include "scene/state/animation.h"

namespace gistream {
namespace animation_test {

using testing::AddQuadMesh;
using testing::Import;
using testing::TestGltf;

constexpr float kTol = 1e-5f;
constexpr int kFloat = 5126;

AnimationSampler Sampler(Interpolation interpolation, std::vector<float> times,
                         std::vector<float> values, int components) {
  AnimationSampler s;
  s.interpolation = interpolation;
  s.times = std::move(times);
  s.values = std::move(values);
  s.components = components;
  return s;
}

void ExpectNear(const std::vector<float>& got, const std::vector<float>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], kTol) << "component " << i;
}

// Keys at 0, 1 and 3 s.
const std::vector<float> kTimes = {0, 1, 3};
const std::vector<float> kTranslations = {0, 0, 0, 2, 4, -2, 2, 0, 0};

TEST(AnimationSample, LinearAtKeysAndBetween) {
  const AnimationSampler s = Sampler(Interpolation::kLinear, kTimes, kTranslations, 3);
  const auto at = [&](float t) { return SampleSampler(s, AnimationPath::kTranslation, t); };
  ExpectNear(at(0), {0, 0, 0});
  ExpectNear(at(1), {2, 4, -2});
  ExpectNear(at(3), {2, 0, 0});
  ExpectNear(at(0.5f), {1, 2, -1});    // halfway through [0, 1]
  ExpectNear(at(2.0f), {2, 2, -1});    // halfway through [1, 3]
  ExpectNear(at(2.5f), {2, 1, -0.5});  // three quarters
}

TEST(AnimationSample, ClampsBeforeStartAndAfterEnd) {
  for (Interpolation i : {Interpolation::kLinear, Interpolation::kStep}) {
    const AnimationSampler s = Sampler(i, kTimes, kTranslations, 3);
    ExpectNear(SampleSampler(s, AnimationPath::kTranslation, -5.0f), {0, 0, 0});
    ExpectNear(SampleSampler(s, AnimationPath::kTranslation, 99.0f), {2, 0, 0});
  }
}

TEST(AnimationSample, StepHoldsTheEarlierKey) {
  const AnimationSampler s = Sampler(Interpolation::kStep, kTimes, kTranslations, 3);
  const auto at = [&](float t) { return SampleSampler(s, AnimationPath::kTranslation, t); };
  ExpectNear(at(0.99f), {0, 0, 0});
  ExpectNear(at(1.0f), {2, 4, -2});
  ExpectNear(at(2.9f), {2, 4, -2});
  ExpectNear(at(3.0f), {2, 0, 0});
}

// Two keys 2 s apart, each stored as in-tangent, value, out-tangent.
// x: v0 = 0, b0 = 1, v1 = 1, a1 = 0;  y: v0 = v1 = 0, b0 = 0, a1 = 3;
// z: constant 5. With td = 2 and u = (t - 0) / 2, Appendix C gives
//   p(u) = (2u^3 - 3u^2 + 1) v0 + td (u^3 - 2u^2 + u) b0
//        + (-2u^3 + 3u^2) v1 + td (u^3 - u^2) a1.
TEST(AnimationSample, CubicSplineHermiteWithTangentsScaledByTheInterval) {
  const std::vector<float> values = {0, 0, 0, /**/ 0, 0, 5, /**/ 1, 0, 0,   // key 0: a0, v0, b0
                                     0, 3, 0, /**/ 1, 0, 5, /**/ 0, 0, 0};  // key 1: a1, v1, b1
  const AnimationSampler s = Sampler(Interpolation::kCubicSpline, {0, 2}, values, 3);
  const auto at = [&](float t) { return SampleSampler(s, AnimationPath::kTranslation, t); };
  ExpectNear(at(0), {0, 0, 5});
  ExpectNear(at(2), {1, 0, 5});
  // u = 0.5: h00 = 0.5, td*h10 = 0.25, h01 = 0.5, td*h11 = -0.25.
  ExpectNear(at(1), {0.25f + 0.5f, -0.75f, 5});
  // u = 0.25: td*h10 = 0.28125, h01 = 0.15625, td*h11 = -0.09375.
  ExpectNear(at(0.5f), {0.28125f + 0.15625f, -0.28125f, 5});
  ExpectNear(at(-1), {0, 0, 5});
  ExpectNear(at(7), {1, 0, 5});
}

glm::vec3 Rotate(const std::vector<float>& xyzw, glm::vec3 v) {
  return glm::quat(xyzw[3], xyzw[0], xyzw[1], xyzw[2]) * v;
}

TEST(AnimationSample, LinearRotationSlerpsOnTheShortestArc) {
  const float h = std::sqrt(0.5f);
  // Identity, then 90 degrees about +Z stored as its negative (-q is the
  // same rotation): the short way from the first key is still +90 degrees.
  const AnimationSampler s =
      Sampler(Interpolation::kLinear, {0, 1}, {0, 0, 0, 1, /**/ 0, 0, -h, -h}, 4);
  for (float t : {0.25f, 0.5f, 0.75f}) {
    const std::vector<float> q = SampleSampler(s, AnimationPath::kRotation, t);
    const float angle = t * 1.5707963f;
    const glm::vec3 x = Rotate(q, {1, 0, 0});
    EXPECT_NEAR(x.x, std::cos(angle), kTol) << t;
    EXPECT_NEAR(x.y, std::sin(angle), kTol) << t;
    EXPECT_NEAR(x.z, 0.0f, kTol) << t;
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0f, kTol);
  }
  // The midpoint is 45 degrees about +Z: (0, 0, sin 22.5, cos 22.5) up to sign.
  const std::vector<float> mid = SampleSampler(s, AnimationPath::kRotation, 0.5f);
  EXPECT_NEAR(std::abs(mid[2]), std::sin(0.39269908f), kTol);
  EXPECT_NEAR(std::abs(mid[3]), std::cos(0.39269908f), kTol);
}

TEST(AnimationSample, CubicSplineRotationIsRenormalised) {
  const float h = std::sqrt(0.5f);
  // Zero tangents: at u = 0.5 the spline is (q0 + q1) / 2, whose normalised
  // form is the 45-degree rotation.
  const std::vector<float> values = {0, 0, 0, 0, /**/ 0, 0, 0, 1, /**/ 0, 0, 0, 0,
                                     0, 0, 0, 0, /**/ 0, 0, h, h, /**/ 0, 0, 0, 0};
  const AnimationSampler s = Sampler(Interpolation::kCubicSpline, {0, 1}, values, 4);
  const std::vector<float> q = SampleSampler(s, AnimationPath::kRotation, 0.5f);
  ExpectNear(q, {0, 0, std::sin(0.39269908f), std::cos(0.39269908f)});
}

TEST(AnimationSample, WeightsInterpolatePerTarget) {
  const AnimationSampler s = Sampler(Interpolation::kLinear, {0, 2}, {0, 1, /**/ 1, -1}, 2);
  ExpectNear(SampleSampler(s, AnimationPath::kWeights, 0.5f), {0.25f, 0.5f});
}

Animation TwoChannels() {
  Animation a;
  a.samplers = {Sampler(Interpolation::kLinear, kTimes, kTranslations, 3),
                Sampler(Interpolation::kStep, {0, 2}, {1, 1, 1, /**/ 2, 2, 2}, 3)};
  a.channels = {{0, 4, AnimationPath::kTranslation}, {1, 4, AnimationPath::kScale}};
  a.start = 0;
  a.end = 3;
  return a;
}

TEST(AnimationSample, SampleAnimationMergesChannelsPerNode) {
  const std::vector<NodeOverride> o = SampleAnimation(TwoChannels(), 2.0f);
  ASSERT_EQ(o.size(), 1u);
  EXPECT_EQ(o[0].node, 4);
  ASSERT_TRUE(o[0].translation && o[0].scale);
  EXPECT_FALSE(o[0].rotation);
  EXPECT_NEAR(o[0].translation->y, 2.0f, kTol);
  EXPECT_NEAR(o[0].scale->x, 2.0f, kTol);

  std::vector<Node> nodes(5);
  nodes[4].rotation = glm::angleAxis(0.3f, glm::vec3(0, 1, 0));
  ApplyOverrides(o, &nodes);
  EXPECT_NEAR(nodes[4].translation.x, 2.0f, kTol);
  EXPECT_NEAR(nodes[4].rotation.w, std::cos(0.15f), kTol);  // untouched
}

TEST(AnimationSample, LoopWrapsIntoTheRange) {
  const Animation a = TwoChannels();
  // 4 s wraps to 1 s; -0.5 s wraps to 2.5 s.
  EXPECT_NEAR(SampleAnimation(a, 4.0f, AnimationTime::kLoop)[0].translation->y, 4.0f, kTol);
  EXPECT_NEAR(SampleAnimation(a, -0.5f, AnimationTime::kLoop)[0].translation->y, 1.0f, kTol);
  // Clamped, 4 s is the end.
  EXPECT_NEAR(SampleAnimation(a, 4.0f)[0].translation->y, 0.0f, kTol);
}

// ------------------------------------------------------------------ import

int AddFloats(TestGltf* g, const std::vector<float>& v, const std::string& type, int n) {
  return g->AddAccessor(g->AddView(v.data(), v.size() * 4), kFloat, v.size() / size_t(n), type);
}

// A quad node (node 0) with a translation animation over keys 0, 1, 3 s.
TestGltf Animated(const std::string& interpolation = "LINEAR") {
  TestGltf g;
  g.AddRoot({{"mesh", AddQuadMesh(&g)}});
  const int input = AddFloats(&g, kTimes, "SCALAR", 1);
  const int output = AddFloats(&g, kTranslations, "VEC3", 3);
  g.doc["animations"] = {
      {{"name", "move"},
       {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
       {"samplers", {{{"input", input}, {"output", output}, {"interpolation", interpolation}}}}}};
  return g;
}

TEST(AnimationImport, ImportsChannelsAndSamplers) {
  absl::StatusOr<Scene> scene = Import(Animated().ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ASSERT_EQ(scene->animations.size(), 1u);
  const Animation& a = scene->animations[0];
  EXPECT_EQ(a.name, "move");
  EXPECT_EQ(a.start, 0.0f);
  EXPECT_EQ(a.end, 3.0f);
  ASSERT_EQ(a.channels.size(), 1u);
  EXPECT_EQ(a.channels[0].node, 0);
  EXPECT_EQ(a.channels[0].path, AnimationPath::kTranslation);
  EXPECT_EQ(a.samplers[0].times, kTimes);
  EXPECT_EQ(a.samplers[0].values, kTranslations);
  ExpectNear(SampleSampler(a.samplers[0], AnimationPath::kTranslation, 0.5f), {1, 2, -1});
}

TEST(AnimationImport, NearUnitRotationsAreRenormalised) {
  TestGltf g = Animated();
  const int output = AddFloats(&g, {0, 0, 0, 1.004f, 0, 0, 0, 1, 0, 0, 0.999f, 0}, "VEC4", 4);
  g.doc["animations"][0]["samplers"][0]["output"] = output;
  g.doc["animations"][0]["channels"][0]["target"]["path"] = "rotation";
  absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ExpectNear(scene->animations[0].samplers[0].values, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0});
}

TEST(AnimationImport, InvalidAnimationsNameTheirJsonPath) {
  TestGltf g = Animated();
  g.doc["animations"][0]["samplers"][0]["input"] = AddFloats(&g, {0, 2, 2}, "SCALAR", 1);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].samplers[0].input: key 2 at 2 s is not after key 1 at 2 s");

  g = Animated();
  g.doc["animations"][0]["samplers"][0]["input"] = AddFloats(&g, {-1, 2, 3}, "SCALAR", 1);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].samplers[0].input: the first key time -1 is negative");

  g = Animated();
  g.doc["animations"][0]["samplers"][0]["input"] = AddFloats(&g, {0, 1, 2}, "VEC3", 3);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "but animations[0].samplers[0].input needs SCALAR");

  g = Animated();
  g.doc["animations"][0]["samplers"][0]["output"] = AddFloats(&g, {0, 0, 0, 1, 1, 1}, "VEC3", 3);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].samplers[0].output: 2 elements, expected 3 (3 keys)");

  g = Animated("CUBICSPLINE");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].samplers[0].output: 3 elements, expected 9 (3 keys x 3 for "
               "CUBICSPLINE)");

  g = Animated("SMOOTH");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].samplers[0].interpolation: 'SMOOTH' is not LINEAR, STEP or "
               "CUBICSPLINE");

  g = Animated();
  g.doc["animations"][0]["channels"][0]["target"]["node"] = 7;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].channels[0].target.node: 7 is out of range (1 nodes)");

  g = Animated();
  g.doc["animations"][0]["channels"][0]["target"].erase("node");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].channels[0].target.node: missing");

  g = Animated();
  g.doc["animations"][0]["channels"][0]["target"]["path"] = "pointer";
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].channels[0].target.path: 'pointer' is not translation");

  g = Animated();
  g.doc["animations"][0]["channels"][0]["sampler"] = 3;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].channels[0].sampler: 3 is out of range (1 samplers)");

  g = Animated();
  g.doc["animations"][0]["channels"].push_back(g.doc["animations"][0]["channels"][0]);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].channels[1].target: nodes[0] translation is already animated by "
               "animations[0].channels[0]");

  g = Animated();
  g.doc["animations"][0]["channels"][0]["target"]["path"] = "weights";
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].channels[0].target: weights of nodes[0], which has no mesh with "
               "morph targets");
}

TEST(AnimationImport, OutputValuesRespectTheLimits) {
  TestGltf g = Animated();
  g.doc["animations"][0]["samplers"][0]["output"] =
      AddFloats(&g, {0, 0, 0, 2e6f, 0, 0, 0, 0, 0}, "VEC3", 3);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "animations[0].samplers[0].output key 1");

  g = Animated();
  g.doc["animations"][0]["channels"][0]["target"]["path"] = "scale";
  g.doc["animations"][0]["samplers"][0]["output"] =
      AddFloats(&g, {1, 1, 1, 1, 0, 1, 1, 1, 1}, "VEC3", 3);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "animations[0].samplers[0].output key 1");

  g = Animated();
  g.doc["animations"][0]["channels"][0]["target"]["path"] = "rotation";
  g.doc["animations"][0]["samplers"][0]["output"] =
      AddFloats(&g, {0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 1}, "VEC4", 4);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].samplers[0].output key 1: zero-length quaternion");

  g = Animated();
  g.doc["animations"][0]["channels"][0]["target"]["path"] = "rotation";
  g.doc["animations"][0]["samplers"][0]["output"] =
      AddFloats(&g, {0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 1}, "VEC4", 4);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].samplers[0].output key 1: length 2 is not 1");
}

TEST(AnimationImport, CubicSplineAndWeightsChannels) {
  TestGltf g = Animated("CUBICSPLINE");
  // Three keys of (in-tangent, value, out-tangent); values 0, 1, 2 on x.
  std::vector<float> cubic;
  for (float v : {0.0f, 1.0f, 2.0f}) cubic.insert(cubic.end(), {9, 9, 9, v, 0, 0, -9, -9, -9});
  g.doc["animations"][0]["samplers"][0]["output"] = AddFloats(&g, cubic, "VEC3", 3);
  // A second node with two morph targets, its weights animated by STEP.
  const int mesh = AddQuadMesh(&g);
  const int d = g.AddVec3(std::vector<float>(12, 0.5f));
  g.doc["meshes"][size_t(mesh)]["primitives"][0]["targets"] = {{{"POSITION", d}},
                                                               {{"POSITION", d}}};
  g.AddRoot({{"mesh", mesh}});
  const int times = AddFloats(&g, {0.5f, 4}, "SCALAR", 1);
  const int weights = AddFloats(&g, {1, 0, /**/ 0.25f, 0.75f}, "SCALAR", 1);
  g.doc["animations"][0]["samplers"].push_back(
      {{"input", times}, {"output", weights}, {"interpolation", "STEP"}});
  g.doc["animations"][0]["channels"].push_back(
      {{"sampler", 1}, {"target", {{"node", 1}, {"path", "weights"}}}});
  absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  const Animation& a = scene->animations[0];
  EXPECT_EQ(a.start, 0.0f);
  EXPECT_EQ(a.end, 4.0f);
  ExpectNear(SampleSampler(a.samplers[0], AnimationPath::kTranslation, 1.0f), {1, 0, 0});
  EXPECT_EQ(a.samplers[1].components, 2);
  const std::vector<NodeOverride> o = SampleAnimation(a, 3.0f);
  ASSERT_EQ(o.size(), 2u);
  ExpectNear(o[1].weights, {1, 0});
  ExpectNear(SampleAnimation(a, 4.0f)[1].weights, {0.25f, 0.75f});

  // Three weights for two targets x two keys is one short.
  g.doc["animations"][0]["samplers"][1]["output"] = AddFloats(&g, {1, 0, 0}, "SCALAR", 1);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].samplers[1].output: 3 elements, expected 4 (2 keys x 2 morph "
               "targets)");
}

TEST(AnimationImport, MemberTypesAreCheckedBeforeParsing) {
  TestGltf g = Animated();
  g.doc["animations"][0]["samplers"][0]["input"] = "a";
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].samplers[0].input: \"a\" is not an index");
  g = Animated();
  g.doc["animations"][0]["samplers"][0].erase("output");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "animations[0].samplers[0].output: missing");
  g = Animated();
  g.doc["animations"][0]["channels"][0]["target"]["node"] = 4294967295u;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "animations[0].channels[0].target.node: 4294967295 is not an index");
}

TEST(AnimationImport, FilesWithoutAnimationsHaveNone) {
  TestGltf g;
  g.AddRoot({{"mesh", AddQuadMesh(&g)}});
  absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_TRUE(scene->animations.empty());
  EXPECT_TRUE(scene->skins.empty());
  EXPECT_TRUE(scene->meshes[0].weights.empty());
  EXPECT_TRUE(scene->meshes[0].primitives[0].joints.empty());
  EXPECT_TRUE(scene->meshes[0].primitives[0].targets.empty());
}

}  // namespace animation_test
}  // namespace gistream
