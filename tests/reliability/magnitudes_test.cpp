// Issue 13, findings 1 (crash: a 1e20 m translation aborted the path
// tracer in Embree) and 3 (+Inf out of finite input): magnitude limits on
// every value of a glTF file or an update (scene/magnitude_limits.h).
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "encode/encode.h"
#include "reliability/reliability_fixture.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace magnitudes_test {

using json = nlohmann::json;

NodeTransformUpdate Translate(uint32_t node, glm::vec3 t) {
  NodeTransformUpdate u;
  u.node = node;
  u.translation = t;
  return u;
}

TEST(Magnitudes, HugeTranslationUpdateIsRejectedAndPathtraceStillRenders) {
  const QuadCopy scene;
  // Used to abort the process in Embree (ray.valid()) on the first frame.
  auto frame = E().Render(Request(scene.id(), "pathtrace", {U(Translate(0, {1e20f, 0, 0}))}));
  EXPECT_STATUS(StatusOf(frame), kInvalidArgument,
                "update.node_transform.translation.x: 1e+20 is beyond the world extent limit");
  ExpectRendersFinite(scene.id(), "pathtrace");
}

TEST(Magnitudes, HugeTranslationInGltfIsRejected) {
  json doc = QuadScene();
  doc["nodes"][0]["translation"] = {1e20, 0, 0};
  EXPECT_STATUS(StatusOf(E().LoadScene(testing::SceneFromBytes(doc.dump()))), kInvalidArgument,
                "nodes[0].translation.x: 1e+20 is beyond the world extent limit");
}

// Each value is within its own limit; their product through the hierarchy
// is not.
TEST(Magnitudes, WorldExtentIsCheckedThroughTheHierarchy) {
  json doc = QuadScene();
  doc["nodes"].push_back({{"name", "parent"}, {"scale", {1e3, 1e3, 1e3}}, {"children", {0}}});
  doc["nodes"][0]["translation"] = {1e4, 0, 0};
  doc["scenes"][0]["nodes"].erase(0);
  doc["scenes"][0]["nodes"].push_back(doc["nodes"].size() - 1);
  EXPECT_STATUS(StatusOf(E().LoadScene(testing::SceneFromBytes(doc.dump()))), kInvalidArgument,
                "nodes[0]: world position.x: 1e+07 is beyond the world extent limit");

  // Loadable at scale 1; an update of the parent's scale would move the
  // floor to 1e7 m: rejected when applied, the scene unchanged.
  doc["nodes"].back()["scale"] = {1, 1, 1};
  const QuadCopy scene(doc);
  NodeTransformUpdate grow;
  grow.node = uint32_t(doc["nodes"].size() - 1);
  grow.scale = glm::vec3(1e3f);
  auto frame = E().Render(Request(scene.id(), "pathtrace", {U(grow)}));
  EXPECT_STATUS(StatusOf(frame), kInvalidArgument,
                "update.node_transform: after it, nodes[0]: world position.x");
  // The floor is at x = 1e4 now, out of the camera's view: the scene still
  // renders (the emissive quad), finite.
  auto next = E().Render(Request(scene.id(), "pathtrace"));
  ASSERT_TRUE(next.ok()) << next.status();
  EXPECT_EQ(testing::DecodeExr(*next).non_finite(), 0u);
}

TEST(Magnitudes, ScaleRotationAndFieldOfViewLimits) {
  const QuadCopy scene;
  NodeTransformUpdate scale;
  scale.scale = glm::vec3(1e30f, 1, 1);
  EXPECT_STATUS(StatusOf(E().Render(Request(scene.id(), "direct", {U(scale)}))), kInvalidArgument,
                "update.node_transform.scale.x: 1e+30 is out of range");
  NodeTransformUpdate zero;
  zero.rotation = glm::quat(0, 0, 0, 0);
  EXPECT_STATUS(StatusOf(E().Render(Request(scene.id(), "direct", {U(zero)}))), kInvalidArgument,
                "update.node_transform.rotation: zero-length quaternion");
  NodeTransformUpdate doubled;
  doubled.rotation = glm::quat(2, 0, 0, 0);
  EXPECT_STATUS(StatusOf(E().Render(Request(scene.id(), "direct", {U(doubled)}))), kInvalidArgument,
                "update.node_transform.rotation: length 2 is not 1");
  CameraUpdate narrow;
  narrow.yfov_degrees = 1e-6f;
  EXPECT_STATUS(StatusOf(E().Render(Request(scene.id(), "direct", {U(narrow)}))), kInvalidArgument,
                "update.camera.yfov_degrees: 1e-06 is out of range [0.1, 179]");
  // Near-unit rotations are exporters' rounding: renormalised, accepted.
  NodeTransformUpdate rounded;
  rounded.rotation = glm::quat(1.001f, 0, 0, 0);
  auto frame = E().Render(Request(scene.id(), "direct", {U(rounded)}));
  ASSERT_TRUE(frame.ok()) << frame.status();
  ExpectRendersFinite(scene.id(), "direct");
}

TEST(Magnitudes, HugeEmissionAndIntensityAreRejected) {
  const QuadCopy scene;
  MaterialUpdate strength;
  strength.material = 1;
  strength.emissive_strength = 3e38f;  // used to render +Inf pixels
  EXPECT_STATUS(StatusOf(E().Render(Request(scene.id(), "direct", {U(strength)}))),
                kInvalidArgument, "update.material.emissive_strength: 3e+38 exceeds the limit");
  LightUpdate intensity;
  intensity.intensity = 3.4e38f;
  EXPECT_STATUS(StatusOf(E().Render(Request(scene.id(), "direct", {U(intensity)}))),
                kInvalidArgument, "update.light.intensity: 3.4e+38 exceeds the limit");
  // Each within its limit, the product with the current state not: the
  // factor goes to 1e5, then strength 1e6 would make 1e11 nits.
  MaterialUpdate factor;
  factor.material = 1;
  factor.emissive = glm::vec3(1e5f);
  MaterialUpdate more;
  more.material = 1;
  more.emissive_strength = 1e6f;
  EXPECT_STATUS(StatusOf(E().Render(Request(scene.id(), "direct", {U(factor, 1), U(more, 2)}))),
                kInvalidArgument,
                "update.material: after it, materials[1]: emissive factor x strength 1e+11");
  MaterialUpdate back;
  back.material = 1;
  back.emissive = glm::vec3(1.0f);
  ASSERT_TRUE(E().Render(Request(scene.id(), "direct", {U(back)})).ok());
  ExpectRendersFinite(scene.id(), "direct");
  ExpectRendersFinite(scene.id(), "pathtrace");
}

TEST(Magnitudes, NegativeOrHugeEnvironmentRadianceIsRejected) {
  std::vector<float> rgba(8 * 4 * 4, 0.5f);
  rgba[0] = -1.0f;
  auto exr = EncodeExr(rgba, 8, 4);
  ASSERT_TRUE(exr.ok()) << exr.status();
  SceneSource source = testing::SceneFromBytes(QuadScene().dump());
  source.environment_bytes = *exr;
  EXPECT_STATUS(StatusOf(E().LoadScene(source)), kInvalidArgument,
                "environment: pixel 0 channel 0 is -1; radiance must not be negative");
  rgba[0] = 0.5f;
  exr = EncodeExr(rgba, 8, 4);
  ASSERT_TRUE(exr.ok());
  source.environment_bytes = *exr;
  source.environment_intensity = 1e38f;
  EXPECT_STATUS(StatusOf(E().LoadScene(source)), kInvalidArgument,
                "environment_intensity: 1e+38 x the map's brightest pixel 0.5 exceeds the limit");
  source.environment_intensity = 1.0f;
  auto info = E().LoadScene(source);
  ASSERT_TRUE(info.ok()) << info.status();
  EnvironmentUpdate env;
  env.intensity = 1e38f;
  EXPECT_STATUS(StatusOf(E().Render(Request(info->id, "direct", {U(env)}))), kInvalidArgument,
                "update.environment.intensity: 1e+38 exceeds the limit");
  ExpectRendersFinite(info->id, "direct");
  EXPECT_TRUE(E().UnloadScene(info->id).ok());
}

}  // namespace magnitudes_test
}  // namespace gistream::reliability
