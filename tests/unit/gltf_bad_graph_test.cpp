// Malformed node graphs, transforms, materials, lights and cameras.
#include <gtest/gtest.h>

#include "gltf_test_util.h"
#include "scene/gltf/gltf_import.h"

namespace gistream {
namespace gltf_bad_graph_test {

using testing::AddQuadMesh;
using testing::Import;
using testing::TestGltf;

TEST(BadGraph, NodeCycle) {
  TestGltf g;
  g.AddRoot({});                   // 0: a root, fine
  g.AddNode({{"children", {2}}});  // 1 -> 2
  g.AddNode({{"children", {3}}});  // 2 -> 3
  g.AddNode({{"children", {1}}});  // 3 -> 1
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "the node graph has a cycle");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "nodes[1] -> nodes[2] -> nodes[3] -> nodes[1]");
}

TEST(BadGraph, NodeIsItsOwnChild) {
  TestGltf g;
  g.AddRoot({{"children", {0}}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "nodes[0].children[0]: node 0 is its own child");
}

TEST(BadGraph, NodeWithTwoParents) {
  TestGltf g;
  const int child = g.AddNode({});
  g.AddRoot({{"children", {child}}});
  g.AddRoot({{"children", {child}}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "nodes[2].children[0]: node 0 already has parent nodes[1]");
  // The same parent listing a child twice is the same fault.
  TestGltf h;
  const int c = h.AddNode({});
  h.AddRoot({{"children", {c, c}}});
  EXPECT_ERROR(Import(h.ToGltf()), kInvalidArgument,
               "nodes[1].children[1]: node 0 already has parent");
}

TEST(BadGraph, ChildOutOfRange) {
  TestGltf g;
  g.AddRoot({{"children", {7}}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "nodes[0].children[0]: 7 is out of range (1 nodes)");
}

TEST(BadGraph, SceneListsAChild) {
  TestGltf g;
  const int child = g.AddNode({});
  g.AddRoot({{"children", {child}}});
  g.doc["scenes"][0]["nodes"].push_back(child);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "scenes[0].nodes[1]: node 0 is not a root (child of nodes[1])");
}

TEST(BadGraph, DefaultSceneOutOfRange) {
  TestGltf g;
  g.AddRoot({});
  g.doc["scene"] = 3;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "scene: 3 is out of range (1 scenes)");
}

TEST(BadGraph, TransformValues) {
  TestGltf g;
  g.AddRoot({{"scale", {1, 0, 1}}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].scale[1]: 0");
  g.doc["nodes"][0] = {{"rotation", {0, 0, 0, 0}}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].rotation: zero-length quaternion");
  g.doc["nodes"][0] = {{"translation", {1, 2}}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].translation: 2 values, expected 3");
}

TEST(BadGraph, MatrixValues) {
  TestGltf g;
  g.AddRoot({{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.5, 0, 0, 0, 1}}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].matrix: bottom row");
  g.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0.5, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].matrix: has shear");
  g.doc["nodes"][0]["matrix"] = {0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].matrix scale[0]: 0");
  g.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1e300, 0, 0, 1};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].matrix[12]: 1e+300 is out of range");
  g.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].matrix: 15 values, expected 16");
}

TEST(BadGraph, MaterialValues) {
  TestGltf g;
  const int mat = g.AddMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {1.5, 0, 0, 1}}}}});
  g.AddRoot({{"mesh", AddQuadMesh(&g, true, mat)}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "materials[0].pbrMetallicRoughness.baseColorFactor[0]: 1.5 is out of range [0, 1]");
  g.doc["materials"][0] = {{"emissiveFactor", {0, -1, 0}}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "materials[0].emissiveFactor[1]: -1");
  g.doc["materials"][0] = {
      {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", -2}}}}}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength: -2");
  g.doc["materials"][0] = {{"pbrMetallicRoughness", {{"roughnessFactor", 2}}}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "materials[0].pbrMetallicRoughness.roughnessFactor: 2 is out of range");
}

// A texture on another coordinate set than TEXCOORD_0 is not read: the file
// loads (it was refused whole), the material renders with its factors, and
// the load's answer says which field was ignored.
TEST(BadGraph, TextureOnSecondUvSetIsIgnoredWithAWarning) {
  TestGltf g;
  g.doc["images"] = {{{"uri", "data:image/png;base64,AAAA"}}};
  g.doc["textures"] = {{{"source", 0}}};
  const int mat = g.AddMaterial(
      {{"emissiveFactor", {1, 0.5, 0}}, {"emissiveTexture", {{"index", 0}, {"texCoord", 1}}}});
  g.AddRoot({{"mesh", AddQuadMesh(&g, true, mat)}});
  auto scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ASSERT_EQ(scene->materials.size(), 1u);
  EXPECT_EQ(scene->materials[0].emissive_texture, -1);
  EXPECT_FLOAT_EQ(scene->materials[0].emissive_factor.y, 0.5f);
  EXPECT_TRUE(scene->images.empty());  // never decoded
  ASSERT_EQ(scene->import_warnings.size(), 1u);
  EXPECT_EQ(scene->import_warnings[0],
            "materials[0].emissiveTexture.texCoord: 1: only TEXCOORD_0 is read; the texture is "
            "ignored (the material renders with its factors)");
  // On the first set it is read (and this image does not decode).
  g.doc["materials"][0]["emissiveTexture"]["texCoord"] = 0;
  EXPECT_FALSE(Import(g.ToGltf()).ok());
}

TestGltf WithLight(nlohmann::json light) {
  TestGltf g;
  g.doc["extensions"]["KHR_lights_punctual"]["lights"] =
      nlohmann::json::array({light});  // {light} is a copy under clang
  g.AddRoot({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  return g;
}

TEST(BadGraph, LightValues) {
  EXPECT_ERROR(Import(WithLight({{"type", "area"}}).ToGltf()), kInvalidArgument,
               "extensions.KHR_lights_punctual.lights[0].type: 'area'");
  EXPECT_ERROR(Import(WithLight({{"type", "point"}, {"intensity", -1}}).ToGltf()), kInvalidArgument,
               "extensions.KHR_lights_punctual.lights[0].intensity: -1");
  EXPECT_ERROR(Import(WithLight({{"type", "point"}, {"color", {1, 1}}}).ToGltf()), kInvalidArgument,
               "lights[0].color: 2 values");
  EXPECT_ERROR(Import(WithLight({{"type", "spot"},
                                 {"spot", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.5}}}})
                          .ToGltf()),
               kInvalidArgument, "lights[0].spot.innerConeAngle: 0.6 is out of range [0, 0.5]");
  EXPECT_ERROR(Import(WithLight({{"type", "spot"}, {"spot", {{"outerConeAngle", 2}}}}).ToGltf()),
               kInvalidArgument, "lights[0].spot.outerConeAngle: 2");
}

TEST(BadGraph, LightIndexOutOfRange) {
  TestGltf g = WithLight({{"type", "point"}});
  g.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 4;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "nodes[0].extensions.KHR_lights_punctual.light: 4 is out of range (1 lights)");
}

TEST(BadGraph, CameraValues) {
  TestGltf g;
  g.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 4}, {"znear", 0.1}}}}};
  g.AddRoot({{"camera", 0}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "cameras[0].perspective.yfov: 4");
  g.doc["cameras"][0]["perspective"] = {{"yfov", 1}, {"znear", 1}, {"zfar", 0.5}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "cameras[0].perspective.zfar: 0.5");
  g.doc["cameras"][0]["perspective"] = {{"yfov", 1}, {"znear", 1e30}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "cameras[0].perspective.znear: 1e+30 is out of range (0, 1e+06] m");
  g.doc["cameras"][0]["perspective"] = {{"yfov", 1e-6}, {"znear", 0.1}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "cameras[0].perspective.yfov: 1e-06");
  g.doc["cameras"][0]["perspective"] = {{"yfov", 1}, {"znear", 0.1}};
  g.doc["nodes"][0]["camera"] = 2;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].camera: 2 is out of range");
}

}  // namespace gltf_bad_graph_test
}  // namespace gistream
