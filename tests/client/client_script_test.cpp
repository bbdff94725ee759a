// Script parsing and per-frame update generation (client/script.h,
// client/timeline.h), against a hand-made LoadSceneResponse.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "script.h"
#include "timeline.h"

namespace gistream::client {
namespace client_script_test {

// Float comparisons: values go through float trig and slerp.
constexpr float kEps = 1e-5f;

v1::LoadSceneResponse TestScene() {
  v1::LoadSceneResponse scene;
  scene.set_scene_id("s1");
  auto* light_node = scene.add_nodes();
  light_node->set_id(0);
  light_node->set_name("light");
  light_node->mutable_translation()->set_y(0.5f);
  light_node->mutable_scale()->set_x(1);
  light_node->mutable_scale()->set_y(1);
  light_node->mutable_scale()->set_z(1);
  auto* block = scene.add_nodes();
  block->set_id(7);
  block->set_name("block");
  block->mutable_translation()->set_x(2.0f);
  // Initial rotation: 90 degrees about +X.
  block->mutable_rotation()->set_x(std::sin(glm::radians(45.0f)));
  block->mutable_rotation()->set_w(std::cos(glm::radians(45.0f)));
  block->mutable_scale()->set_x(2);
  block->mutable_scale()->set_y(2);
  block->mutable_scale()->set_z(2);
  for (uint32_t id : {8u, 9u}) {
    auto* twin = scene.add_nodes();
    twin->set_id(id);
    twin->set_name("twin");
  }
  auto* light = scene.add_lights();
  light->set_id(0);
  light->set_name("point_light");
  auto* white = scene.add_materials();
  white->set_id(3);
  white->set_name("white");
  return scene;
}

Script Parse(const std::string& text) {
  auto script = ParseScript(text, "test.json");
  EXPECT_TRUE(script.ok()) << script.status();
  return script.ok() ? *script : Script{};
}

std::string ParseError(const std::string& text) {
  auto script = ParseScript(text, "test.json");
  EXPECT_FALSE(script.ok());
  return script.ok() ? "" : std::string(script.status().message());
}

Timeline Build(const std::string& text) {
  auto timeline = Timeline::Build(Parse(text), TestScene());
  EXPECT_TRUE(timeline.ok()) << timeline.status();
  return *std::move(timeline);
}

void ExpectVec(const v1::Vec3& actual, glm::vec3 expected) {
  EXPECT_NEAR(actual.x(), expected.x, kEps);
  EXPECT_NEAR(actual.y(), expected.y, kEps);
  EXPECT_NEAR(actual.z(), expected.z, kEps);
}

TEST(ScriptParse, BundledOrbitExample) {
  const std::string path = std::string(GISTREAM_SOURCE_DIR "/scenes/cornell_orbit.json");
  auto script = LoadScriptFile(path);
  ASSERT_TRUE(script.ok()) << script.status();
  EXPECT_EQ(script->scene, "cornell_box");
  EXPECT_GT(script->frames, 0);
  EXPECT_FALSE(script->tracks.empty());
}

TEST(ScriptParse, HeaderFieldsAndDefaults) {
  Script script = Parse(R"({"scene": "cornell_box", "frames": 4,
      "params": {"area_samples": 32, "mode": "fast", "filter": true, "scale": 0.5},
      "size": [64, 48], "format": "png", "quality": 80, "exposure": -1.5})");
  EXPECT_EQ(script.solver, "direct");
  EXPECT_EQ(script.params.at("area_samples"), "32");
  EXPECT_EQ(script.params.at("mode"), "fast");
  EXPECT_EQ(script.params.at("filter"), "true");
  EXPECT_EQ(script.params.at("scale"), "0.5");
  EXPECT_EQ(script.width, 64u);
  EXPECT_EQ(script.height, 48u);
  EXPECT_EQ(script.encoding.format(), v1::IMAGE_FORMAT_PNG);
  EXPECT_EQ(script.encoding.quality(), 80u);
  EXPECT_FLOAT_EQ(script.encoding.exposure(), -1.5f);

  Script defaults = Parse(R"({"scene": "x", "frames": 1})");
  EXPECT_EQ(defaults.width, 320u);
  EXPECT_EQ(defaults.height, 240u);
  EXPECT_EQ(defaults.encoding.format(), v1::IMAGE_FORMAT_JPEG);
}

TEST(ScriptParse, NumbersPastADoubleAreAnErrorNotAnException) {
  // Found by tests/fuzz/script_fuzzer: nlohmann throws out_of_range (not a
  // parse_error) for them, which ended the client.
  EXPECT_NE(ParseError(R"({"scene": "x", "frames": 8e888})").find("test.json: not valid JSON: "),
            std::string::npos);
}

TEST(ScriptParse, ErrorsNameTheJsonPath) {
  EXPECT_EQ(ParseError(R"({"frames": 3})"), "test.json: scene: required");
  EXPECT_EQ(ParseError(R"({"scene": "x"})"), "test.json: frames: required");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 0})"),
            "test.json: frames: 0 is out of range [1, 1000000]");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "camera_orbit",
      "target": [0, 0, 0], "radius": 1, "height": 0, "start_deg": 0, "end_deg": 90},
      {"type": "node_path", "node": "light", "keys": [{"frame": 0, "translation": [1, 2]}]}]})"),
            "test.json: tracks[1].keys[0].translation: expected 3 numbers");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "camera_orbit",
      "target": [0, 0, 0], "radus": 1}]})"),
            "test.json: tracks[0].radus: unknown key (expected type, target, radius, height, "
            "start_deg, end_deg, yfov_degrees)");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "warp"}]})"),
            "test.json: tracks[0].type: unknown track type \"warp\" (expected camera_orbit, "
            "camera_path, node_path, node_spin, light, material, environment)");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "light",
      "light": 0, "keys": [{"frame": 5, "intensity": 1}, {"frame": 5, "intensity": 2}]}]})"),
            "test.json: tracks[0].keys[1].frame: 5 is not after the previous key's frame 5");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "light",
      "light": 0, "keys": [{"frame": 0}]}]})"),
            "test.json: tracks[0].keys[0]: no value (expected intensity, color, position, "
            "direction, inner_cone_angle, outer_cone_angle)");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "light",
      "light": 0, "keys": [{"frame": 0, "intensity": -1}]}]})"),
            "test.json: tracks[0].keys[0].intensity: -1 is negative");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "node_spin",
      "node": 1.5, "degrees_per_frame": 1}]})"),
            "test.json: tracks[0].node: expected a name or a numeric id");
  EXPECT_EQ(
      ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "node_path",
      "node": "a", "keys": [{"frame": 0, "rotation": [0, 0, 0, 0]}]}]})"),
      "test.json: tracks[0].keys[0].rotation: zero-length quaternion (expected [x, y, z, w])");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "material",
      "material": 0, "keys": [{"frame": 0, "base_color": [1, 1, 1]},
      {"frame": 1, "base_color": [1, 1, 1, 1]}]}]})"),
            "test.json: tracks[0].keys[1].base_color: 4 numbers, but earlier keys have 3");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [
      {"type": "camera_path", "keys": [{"frame": 0, "eye": [0, 0, 1], "target": [0, 0, 0]}]},
      {"type": "camera_orbit", "target": [0, 0, 0], "radius": 1, "height": 0, "start_deg": 0,
       "end_deg": 1}]})"),
            "test.json: tracks[1]: a second camera track (tracks[0] is one); keep one "
            "camera_orbit or camera_path");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "size": [0, 10]})"),
            "test.json: size[0]: 0 is out of range [1, 16384]");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "format": "gif"})"),
            "test.json: format: unknown image format \"gif\" (expected jpeg, png, exr, h264, hevc "
            "or av1)");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "events": [{"frame": 3,
      "update": {"environment": {"intensity": 2}}}]})"),
            "test.json: events[0].frame: 3 is out of range [0, 2]");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "events": [{"frame": 0, "update": {}}]})"),
            "test.json: events[0].update: no change (expected one of node_transform, light, "
            "camera, material, environment)");
  EXPECT_NE(ParseError(R"({"scene": "x", "frames": 3, "events": [{"frame": 0,
      "update": {"bogus": 1}}]})")
                .find("test.json: events[0].update: not a gistream.v1.Update"),
            std::string::npos);
  EXPECT_NE(ParseError("{\"scene\": ").find("test.json: not valid JSON"), std::string::npos);
}

TEST(Curve, LinearBetweenKeysHeldOutside) {
  Curve<float> curve;
  curve.keys = {{2, 10.0f}, {6, 30.0f}, {8, 0.0f}};
  EXPECT_FLOAT_EQ(curve.At(0), 10.0f);  // before the first key
  EXPECT_FLOAT_EQ(curve.At(2), 10.0f);
  EXPECT_FLOAT_EQ(curve.At(3), 15.0f);
  EXPECT_FLOAT_EQ(curve.At(6), 30.0f);
  EXPECT_FLOAT_EQ(curve.At(7), 15.0f);
  EXPECT_FLOAT_EQ(curve.At(8), 0.0f);
  EXPECT_FLOAT_EQ(curve.At(100), 0.0f);  // held after the last key
}

TEST(Timeline, CameraOrbitFollowsTheCircle) {
  Timeline timeline = Build(R"({"scene": "x", "frames": 3, "tracks": [{"type": "camera_orbit",
      "target": [1, 2, 3], "radius": 2, "height": 5, "start_deg": -90, "end_deg": 90,
      "yfov_degrees": 40}]})");
  // a = -90, 0, 90 degrees.
  const glm::vec3 expected[] = {{1, 5, 1}, {3, 5, 3}, {1, 5, 5}};
  for (int i = 0; i < 3; ++i) {
    auto updates = timeline.UpdatesForFrame(i);
    ASSERT_EQ(updates.size(), 1u) << "frame " << i;
    const v1::CameraChange& camera = updates[0].camera();
    ASSERT_TRUE(camera.has_look_at());
    ExpectVec(camera.look_at().eye(), expected[i]);
    ExpectVec(camera.look_at().target(), {1, 2, 3});
    ExpectVec(camera.look_at().up(), {0, 1, 0});
    EXPECT_FLOAT_EQ(camera.yfov_degrees(), 40.0f);
    EXPECT_EQ(updates[0].seq(), 0u);  // assigned when sent
  }
}

TEST(Timeline, SingleFrameOrbitUsesStartAngle) {
  Timeline timeline = Build(R"({"scene": "x", "frames": 1, "tracks": [{"type": "camera_orbit",
      "target": [0, 0, 0], "radius": 1, "height": 0, "start_deg": 0, "end_deg": 90}]})");
  auto updates = timeline.UpdatesForFrame(0);
  ASSERT_EQ(updates.size(), 1u);
  ExpectVec(updates[0].camera().look_at().eye(), {1, 0, 0});
  EXPECT_FALSE(updates[0].camera().has_yfov_degrees());
}

TEST(Timeline, NodePathSendsOnlyChangesAndKeepsOtherTrs) {
  Timeline timeline = Build(R"({"scene": "x", "frames": 6, "tracks": [{"type": "node_path",
      "node": "block", "keys": [{"frame": 0, "translation": [0, 0, 0]},
                                {"frame": 2, "translation": [2, 0, 4]}]}]})");
  auto first = timeline.UpdatesForFrame(0);
  ASSERT_EQ(first.size(), 1u);
  const v1::NodeTransform& t0 = first[0].node_transform();
  EXPECT_EQ(t0.node(), 7u);
  ExpectVec(t0.translation(), {0, 0, 0});
  ExpectVec(t0.scale(), {2, 2, 2});  // from the scene, not zero
  EXPECT_NEAR(t0.rotation().x(), std::sin(glm::radians(45.0f)), kEps);
  EXPECT_NEAR(t0.rotation().w(), std::cos(glm::radians(45.0f)), kEps);

  auto second = timeline.UpdatesForFrame(1);
  ASSERT_EQ(second.size(), 1u);
  ExpectVec(second[0].node_transform().translation(), {1, 0, 2});
  ASSERT_EQ(timeline.UpdatesForFrame(2).size(), 1u);
  // Held after the last key: nothing more to send.
  EXPECT_TRUE(timeline.UpdatesForFrame(3).empty());
  EXPECT_TRUE(timeline.UpdatesForFrame(5).empty());
}

TEST(Timeline, NodeSpinComposesWithInitialRotation) {
  Timeline timeline = Build(R"({"scene": "x", "frames": 3, "tracks": [{"type": "node_spin",
      "node": 7, "axis": [0, 2, 0], "degrees_per_frame": 90}]})");
  const glm::quat initial = glm::angleAxis(glm::radians(90.0f), glm::vec3(1, 0, 0));
  for (int i = 0; i < 3; ++i) {
    auto updates = timeline.UpdatesForFrame(i);
    ASSERT_EQ(updates.size(), 1u);
    const v1::NodeTransform& t = updates[0].node_transform();
    const glm::quat expected =
        glm::angleAxis(glm::radians(90.0f * static_cast<float>(i)), glm::vec3(0, 1, 0)) * initial;
    const glm::quat actual(t.rotation().w(), t.rotation().x(), t.rotation().y(), t.rotation().z());
    EXPECT_NEAR(std::fabs(glm::dot(actual, expected)), 1.0f, kEps) << "frame " << i;
    ExpectVec(t.translation(), {2, 0, 0});
    ExpectVec(t.scale(), {2, 2, 2});
  }
}

TEST(Timeline, PathAndSpinOnOneNodeMakeOneUpdate) {
  Timeline timeline = Build(R"({"scene": "x", "frames": 2, "tracks": [
      {"type": "node_spin", "node": "block", "degrees_per_frame": 10},
      {"type": "node_path", "node": "block", "keys": [{"frame": 0, "translation": [0, 1, 0]}]}]})");
  auto updates = timeline.UpdatesForFrame(1);
  ASSERT_EQ(updates.size(), 1u);
  ExpectVec(updates[0].node_transform().translation(), {0, 1, 0});
}

TEST(Timeline, LightAndMaterialKeysSetOnlyKeyedFields) {
  Timeline timeline = Build(R"({"scene": "x", "frames": 30, "tracks": [
      {"type": "light", "light": "point_light", "keys": [
          {"frame": 0, "intensity": 100, "color": [1, 1, 1], "position": [0, 2, 0]},
          {"frame": 20, "intensity": 300}]},
      {"type": "material", "material": "white", "keys": [
          {"frame": 0, "base_color": [0.7, 0.7, 0.7]}]}]})");
  auto first = timeline.UpdatesForFrame(0);
  ASSERT_EQ(first.size(), 2u);
  const v1::LightChange& light = first[0].light();
  EXPECT_EQ(light.light(), 0u);
  EXPECT_FLOAT_EQ(light.intensity(), 100.0f);
  ExpectVec(light.color(), {1, 1, 1});
  ExpectVec(light.position(), {0, 2, 0});
  EXPECT_FALSE(light.has_direction());
  EXPECT_FALSE(light.has_inner_cone_angle());
  const v1::MaterialChange& material = first[1].material();
  EXPECT_EQ(material.material(), 3u);
  ASSERT_EQ(material.base_color_size(), 3);  // RGB keys send RGB
  EXPECT_FLOAT_EQ(material.base_color(0), 0.7f);
  EXPECT_FALSE(material.has_emissive());

  auto tenth = timeline.UpdatesForFrame(10);
  ASSERT_EQ(tenth.size(), 1u);  // the material holds still
  EXPECT_FLOAT_EQ(tenth[0].light().intensity(), 200.0f);
  EXPECT_TRUE(timeline.UpdatesForFrame(21).empty());
}

TEST(Timeline, MaterialKeysSetMetallicAndRoughness) {
  // Issue 18's glossy materials: metallic and roughness keys, interpolated
  // like the others, sent as MaterialChange fields 5 and 6; nothing else set.
  Timeline timeline = Build(R"({"scene": "x", "frames": 11, "tracks": [
      {"type": "material", "material": "white", "keys": [
          {"frame": 0, "metallic": 0, "roughness": 1},
          {"frame": 10, "metallic": 1, "roughness": 0.2}]}]})");
  auto first = timeline.UpdatesForFrame(0);
  ASSERT_EQ(first.size(), 1u);
  const v1::MaterialChange& material = first[0].material();
  EXPECT_EQ(material.material(), 3u);
  ASSERT_TRUE(material.has_metallic() && material.has_roughness());
  EXPECT_FLOAT_EQ(material.metallic(), 0.0f);
  EXPECT_FLOAT_EQ(material.roughness(), 1.0f);
  EXPECT_EQ(material.base_color_size(), 0);
  EXPECT_FALSE(material.has_emissive() || material.has_emissive_strength());
  auto fifth = timeline.UpdatesForFrame(5);
  ASSERT_EQ(fifth.size(), 1u);
  EXPECT_NEAR(fifth[0].material().metallic(), 0.5f, kEps);
  EXPECT_NEAR(fifth[0].material().roughness(), 0.6f, kEps);

  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "material",
      "material": 0, "keys": [{"frame": 0, "roughness": 1.5}]}]})"),
            "test.json: tracks[0].keys[0].roughness: 1.5 is outside [0, 1]");
  EXPECT_EQ(ParseError(R"({"scene": "x", "frames": 3, "tracks": [{"type": "material",
      "material": 0, "keys": [{"frame": 0, "metallic": -0.1}]}]})"),
            "test.json: tracks[0].keys[0].metallic: -0.1 is outside [0, 1]");
}

TEST(Timeline, EventsFollowTrackUpdates) {
  Timeline timeline = Build(R"({"scene": "x", "frames": 12, "tracks": [
      {"type": "node_spin", "node": "light", "degrees_per_frame": 5}],
      "events": [{"frame": 10, "update": {"environment": {"intensity": 2.0}}},
                 {"frame": 10, "update": {"seq": 99, "light": {"light": 0, "intensity": 5}}}]})");
  EXPECT_EQ(timeline.UpdatesForFrame(9).size(), 1u);
  auto updates = timeline.UpdatesForFrame(10);
  ASSERT_EQ(updates.size(), 3u);
  EXPECT_TRUE(updates[0].has_node_transform());
  ASSERT_TRUE(updates[1].has_environment());
  EXPECT_FLOAT_EQ(updates[1].environment().intensity(), 2.0f);
  EXPECT_TRUE(updates[2].has_light());
  EXPECT_EQ(updates[2].seq(), 0u);  // the client assigns seq
}

TEST(Timeline, EnvironmentAndCameraPathTracks) {
  Timeline timeline = Build(R"({"scene": "x", "frames": 3, "tracks": [
      {"type": "camera_path", "keys": [{"frame": 0, "eye": [0, 0, 4], "target": [0, 0, 0]},
                                       {"frame": 2, "eye": [0, 0, 2], "yfov_degrees": 30}]},
      {"type": "environment", "keys": [{"frame": 0, "rotation": 0}, {"frame": 2, "rotation": 1}]}]})");
  auto updates = timeline.UpdatesForFrame(1);
  ASSERT_EQ(updates.size(), 2u);
  ExpectVec(updates[0].camera().look_at().eye(), {0, 0, 3});
  EXPECT_FLOAT_EQ(updates[0].camera().yfov_degrees(), 30.0f);
  EXPECT_FLOAT_EQ(updates[1].environment().rotation(), 0.5f);
  EXPECT_FALSE(updates[1].environment().has_intensity());
}

TEST(Timeline, UnknownAndAmbiguousNamesFailBeforeStreaming) {
  auto unknown = Timeline::Build(Parse(R"({"scene": "x", "frames": 1, "tracks": [
      {"type": "node_spin", "node": "lamp", "degrees_per_frame": 5}]})"),
                                 TestScene());
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(
      unknown.status().message(),
      "tracks[0].node: the scene has no node named \"lamp\" (nodes: light, block, twin, twin)");
  auto ambiguous = Timeline::Build(Parse(R"({"scene": "x", "frames": 1, "tracks": [
      {"type": "node_spin", "node": "twin", "degrees_per_frame": 5}]})"),
                                   TestScene());
  ASSERT_FALSE(ambiguous.ok());
  EXPECT_EQ(ambiguous.status().message(),
            "tracks[0].node: 2 nodes are named \"twin\"; name it by id (one of 8, 9)");
  auto bad_id = Timeline::Build(Parse(R"({"scene": "x", "frames": 1, "tracks": [
      {"type": "material", "material": 4, "keys": [{"frame": 0, "emissive": [1, 1, 1]}]}]})"),
                                TestScene());
  ASSERT_FALSE(bad_id.ok());
  EXPECT_EQ(bad_id.status().message(), "tracks[0].material: the scene has no material with id 4");
}

}  // namespace client_script_test
}  // namespace gistream::client
