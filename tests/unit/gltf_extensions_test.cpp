// The glTF extensions a file uses that gistream renders without are
// reported (Scene::ignored_extensions -> LoadSceneResponse), so a client
// knows why a picture may differ from another renderer's (issue 29).
#include <gtest/gtest.h>

#include "gltf_test_util.h"

namespace gistream::testing {
namespace {

using nlohmann::json;

TEST(GltfExtensions, AWallWithoutSpecularIsLambertian) {
  TestGltf gltf;
  // A wall as exporters write it: roughness 0.9 with ior 1 and specular
  // factor 0, Lambertian where they are read. Import makes it the BRDF's
  // Lambertian case exactly (metallic 0, roughness 1), so neither extension
  // is ignored; the one import reads besides is applied.
  const int material = gltf.AddMaterial(
      {{"pbrMetallicRoughness", {{"roughnessFactor", 0.9}, {"metallicFactor", 0.0}}},
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
  EXPECT_TRUE(scene->ignored_extensions.empty());
  EXPECT_EQ(scene->materials[0].roughness_factor, 1.0f);
  EXPECT_EQ(scene->materials[0].metallic_factor, 0.0f);
  EXPECT_EQ(scene->materials[0].metallic_roughness_texture, -1);
  EXPECT_FLOAT_EQ(scene->materials[0].emissive_strength, 2.0f);
}

TEST(GltfExtensions, DielectricSpecularTheBrdfCannotFollowIsReported) {
  // F0 = ((ior - 1) / (ior + 1))^2 specularColorFactor specularFactor and
  // F90 = specularFactor against the BRDF's 0.04 and 1.
  struct Case {
    json extensions;
    double metallic;
    bool ignored;
  };
  const std::vector<Case> cases = {
      // ior 1.5, no specular extension: F0 0.04, F90 1, the BRDF's own.
      {{{"KHR_materials_ior", {{"ior", 1.5}}}}, 0.0, false},
      {{{"KHR_materials_specular", {{"specularFactor", 1.0}}}}, 0.0, false},
      // Water's F0 0.02; ior 1 with the default specular (F0 0, F90 1).
      {{{"KHR_materials_ior", {{"ior", 1.33}}}}, 0.0, true},
      {{{"KHR_materials_ior", {{"ior", 1.0}}}}, 0.0, true},
      // A tinted or textured specular layer.
      {{{"KHR_materials_specular", {{"specularColorFactor", {1.0, 0.5, 0.5}}}}}, 0.0, true},
      {{{"KHR_materials_specular", {{"specularTexture", {{"index", 0}}}}}}, 0.0, true},
      // No specular layer on a metal: the metallic lobe stays, not exact.
      {{{"KHR_materials_specular", {{"specularFactor", 0.0}}}}, 1.0, true},
  };
  for (const Case& c : cases) {
    TestGltf gltf;
    const int material = gltf.AddMaterial(
        {{"pbrMetallicRoughness", {{"metallicFactor", c.metallic}}}, {"extensions", c.extensions}});
    gltf.AddRoot({{"mesh", AddQuadMesh(&gltf, true, material)}});
    auto scene = Import(gltf.ToGltf());
    ASSERT_TRUE(scene.ok()) << scene.status() << " " << c.extensions.dump();
    EXPECT_EQ(!scene->ignored_extensions.empty(), c.ignored) << c.extensions.dump();
    if (!c.ignored) {
      EXPECT_EQ(scene->materials[0].roughness_factor, 1.0f) << c.extensions.dump();  // unchanged
    }
  }
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
