// Clip planes and camera rays at extreme scene scales (issue 14). A lamp
// (a 0.13 x 0.105 emissive quad, L = 1, black) hangs 0.5 mm below a
// ceiling, as in the Cornell box, over a floor; the whole scene — and the
// glTF camera's znear — is authored at scale s. At s = 1e5 the old near
// plane (clamped to at most 1 m, glTF znear ignored) left a depth
// resolution of ~200 m at the lamp's distance against a 50 m gap: the
// ceiling won the depth test and the lamp vanished. Below it the near
// plane (at least 1e-6 m) clipped small scenes.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/gltf_builder.h"
#include "support/render_helpers.h"

namespace gistream {
namespace camera_scale_test {

using testing::GltfBuilder;

constexpr uint32_t kSize = 16;
// Camera at (0, 0.2, -0.5) s looking at the lamp's centre (0, 0.5495, 0) s.
const glm::vec3 kEye(0.0f, 0.2f, -0.5f), kLamp(0.0f, 0.5495f, 0.0f);

std::string LampScene(float s) {
  GltfBuilder b;
  const int lamp = b.AddMaterial("lamp", {0, 0, 0}, {1, 1, 1});
  const int grey = b.AddMaterial("grey", {0.5f, 0.5f, 0.5f});
  b.AddQuad("floor", {0, 0, 0}, {0, 0, 0.5f * s}, {0.5f * s, 0, 0}, grey, 4);             // +Y
  b.AddQuad("ceiling", {0, 0.55f * s, 0}, {0.5f * s, 0, 0}, {0, 0, 0.5f * s}, grey, 4);   // -Y
  b.AddQuad("lamp", {0, kLamp.y * s, 0}, {0.065f * s, 0, 0}, {0, 0, 0.0525f * s}, lamp);  // -Y
  const glm::vec3 f = glm::normalize(kLamp - kEye);
  b.AddCamera("camera", {kEye.x * s, kEye.y * s, kEye.z * s}, {f.x, f.y, f.z}, {0, 1, 0},
              0.349f /* 20 degrees */, 0.01f * s);
  auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(b.ToJson()));
  EXPECT_TRUE(info.ok()) << info.status();
  return info.ok() ? info->id : "";
}

CameraUpdate LookAtLamp(float s) {
  CameraUpdate camera;
  camera.look_at = LookAt{kEye * s, kLamp * s, {0, 1, 0}};
  camera.yfov_degrees = 20.0f;
  return camera;
}

class CameraScale : public ::testing::TestWithParam<float> {};

TEST_P(CameraScale, LampIsNotClippedNorHiddenByTheCeiling) {
  // The lamp fills the image's centre (it subtends ~12 of the 20 degrees):
  // its pixels show L_e = 1 exactly (black, so no reflected light), with
  // the glTF camera (its znear scaled with the scene) and with a client
  // look-at view (planes fitted to the geometry). The floor below is lit.
  const float s = GetParam();
  const std::string id = LampScene(s);
  ASSERT_FALSE(id.empty());
  for (const bool scene_camera : {true, false}) {
    SCOPED_TRACE(scene_camera ? "glTF camera" : "look-at view");
    std::optional<CameraUpdate> camera;
    if (!scene_camera) camera = LookAtLamp(s);
    const testing::FloatImage image =
        testing::RenderExr(testing::SharedEngine(), id, "direct", kSize, kSize, {}, camera);
    ASSERT_EQ(image.width, int(kSize));
    EXPECT_EQ(image.non_finite(), 0u);
    const glm::vec3 centre = image.mean(int(kSize) / 2, int(kSize) / 2, 1);
    EXPECT_NEAR(centre.g, 1.0f, 0.01f) << "scale " << s;
  }
  (void)testing::SharedEngine().UnloadScene(id);
}

INSTANTIATE_TEST_SUITE_P(Scales, CameraScale, ::testing::Values(1e-4f, 1.0f, 1e5f));

// The same lamp scene authored at unit size under a root node of scale s
// (issue 29): the glTF camera's world matrix then carries s too. Below
// s ~ 4.9e-3 its determinant fell under glm::decompose's epsilon, the
// decomposition failed unnoticed and every solver drew a black frame.
TEST(CameraScaledRoot, TheGltfCameraSeesTheLampAtAnyRootScale) {
  for (const float s : {1e-6f, 1e-3f, 1e4f}) {
    SCOPED_TRACE(::testing::Message() << "root scale " << s);
    GltfBuilder b;
    const int lamp = b.AddMaterial("lamp", {0, 0, 0}, {1, 1, 1});
    const int grey = b.AddMaterial("grey", {0.5f, 0.5f, 0.5f});
    b.AddQuad("floor", {0, 0, 0}, {0, 0, 0.5f}, {0.5f, 0, 0}, grey, 4);
    b.AddQuad("ceiling", {0, 0.55f, 0}, {0.5f, 0, 0}, {0, 0, 0.5f}, grey, 4);
    b.AddQuad("lamp", {0, kLamp.y, 0}, {0.065f, 0, 0}, {0, 0, 0.0525f}, lamp);
    const glm::vec3 f = glm::normalize(kLamp - kEye);
    b.AddCamera("camera", {kEye.x, kEye.y, kEye.z}, {f.x, f.y, f.z}, {0, 1, 0}, 0.349f, 0.01f);
    nlohmann::json doc = nlohmann::json::parse(b.ToJson());
    nlohmann::json root = {
        {"name", "root"}, {"scale", {s, s, s}}, {"children", nlohmann::json::array()}};
    for (const auto& n : doc["scenes"][0]["nodes"]) root["children"].push_back(n);
    doc["nodes"].push_back(root);
    doc["scenes"][0]["nodes"] = nlohmann::json::array({doc["nodes"].size() - 1});
    auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(doc.dump()));
    ASSERT_TRUE(info.ok()) << info.status();
    const testing::FloatImage image =
        testing::RenderExr(testing::SharedEngine(), info->id, "direct", kSize, kSize, {});
    EXPECT_EQ(image.non_finite(), 0u);
    EXPECT_NEAR(image.mean(int(kSize) / 2, int(kSize) / 2, 1).g, 1.0f, 0.01f);
    (void)testing::SharedEngine().UnloadScene(info->id);
  }
}

TEST(CameraScalePathtrace, SameImageAtAnyScale) {
  // Camera rays from the basis and tan(yfov/2): the image does not depend
  // on the scale (same seed, same samples). 64 spp at 16 x 16; the images
  // at scale s and 1 differ only by float rounding of the geometry, so
  // their means agree far within the 1 % allowed (the old inverted
  // projection matrix lost 5.5 % at 1e6).
  const std::string unit = LampScene(1.0f);
  ASSERT_FALSE(unit.empty());
  const std::map<std::string, std::string> params = {{"spp", "64"}};
  const glm::dvec3 reference = testing::ImageMean(
      testing::RenderExr(testing::SharedEngine(), unit, "pathtrace", kSize, kSize, params));
  (void)testing::SharedEngine().UnloadScene(unit);
  ASSERT_GT(reference.g, 0.0);
  for (const float s : {1e-4f, 1e5f, 1e6f}) {
    const std::string id = LampScene(s);
    ASSERT_FALSE(id.empty());
    const glm::dvec3 mean = testing::ImageMean(
        testing::RenderExr(testing::SharedEngine(), id, "pathtrace", kSize, kSize, params));
    EXPECT_NEAR(mean.g, reference.g, 0.01 * reference.g) << "scale " << s;
    (void)testing::SharedEngine().UnloadScene(id);
  }
}

}  // namespace camera_scale_test
}  // namespace gistream
