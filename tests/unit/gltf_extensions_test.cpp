// The glTF extensions a file uses that gistream renders without are
// reported (Scene::ignored_extensions -> LoadSceneResponse), so a client
// knows why a picture may differ from another renderer's (issue 29).
#include <gtest/gtest.h>

#include "gltf_test_util.h"

namespace gistream::testing {
namespace {

using nlohmann::json;

TEST(GltfExtensions, MaterialExtensionsWeDoNotReadAreReported) {
  TestGltf gltf;
  // A wall as exporters write it: roughness 0.9 with ior 1 and a specular
  // factor (Lambertian in a renderer that reads them), a transformed
  // texture coordinate, and the two extensions import does read.
  const int material =
      gltf.AddMaterial({{"pbrMetallicRoughness", {{"roughnessFactor", 0.9}}},
                        {"emissiveFactor", {1.0, 1.0, 1.0}},
                        {"extensions",
                         {{"KHR_materials_ior", {{"ior", 1.0}}},
                          {"KHR_materials_specular", {{"specularFactor", 0.0}}},
                          {"KHR_materials_emissive_strength", {{"emissiveStrength", 2.0}}}}}});
  gltf.AddRoot({{"mesh", AddQuadMesh(&gltf, true, material)}});
  gltf.doc["extensionsUsed"] = {"KHR_materials_ior", "KHR_materials_specular",
                                "KHR_materials_emissive_strength", "KHR_lights_punctual"};
  auto scene = Import(gltf.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_EQ(scene->ignored_extensions,
            (std::vector<std::string>{"KHR_materials_ior", "KHR_materials_specular"}));
  // The extension it does read is applied.
  EXPECT_FLOAT_EQ(scene->materials[0].emissive_strength, 2.0f);
}

TEST(GltfExtensions, AnUndeclaredExtensionIsReportedToo) {
  TestGltf gltf;
  const int material =
      gltf.AddMaterial({{"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}}}}}});
  gltf.AddRoot({{"mesh", AddQuadMesh(&gltf, true, material)}});
  auto scene = Import(gltf.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_EQ(scene->ignored_extensions, (std::vector<std::string>{"KHR_materials_clearcoat"}));
}

TEST(GltfExtensions, AFileWithoutExtensionsReportsNone) {
  TestGltf gltf;
  gltf.AddRoot({{"mesh", AddQuadMesh(&gltf)}});
  auto scene = Import(gltf.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_TRUE(scene->ignored_extensions.empty());
}

}  // namespace
}  // namespace gistream::testing
