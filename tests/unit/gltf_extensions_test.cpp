// The glTF extensions a file uses that gistream renders without are
// reported (Scene::ignored_extensions -> LoadSceneResponse), so a client
// knows why a picture may differ from another renderer's (issue 29).
#include <gtest/gtest.h>

#include "gltf_test_util.h"

namespace gistream::testing {
namespace gltf_extensions_test {

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

// KHR_materials_ior and KHR_materials_specular set the dielectric layer's
// Fresnel, which the BRDF reads (Material::specular_f0 / specular_f90):
// F0 = min(((ior - 1) / (ior + 1))^2 specularColorFactor, 1)
// specularFactor, F90 = specularFactor. Only what it cannot follow (a
// specular texture, an ior below 1) is reported, its factors applied.
TEST(GltfExtensions, DielectricSpecularSetsTheMaterialsFresnel) {
  struct Case {
    json extensions;
    double metallic;
    glm::vec3 f0;
    float f90;
    bool ignored;
  };
  const std::vector<Case> cases = {
      // ior 1.5, no specular extension: F0 0.04, F90 1, the default.
      {{{"KHR_materials_ior", {{"ior", 1.5}}}}, 0.0, glm::vec3(0.04f), 1.0f, false},
      {{{"KHR_materials_specular", {{"specularFactor", 1.0}}}}, 0.0, glm::vec3(0.04f), 1.0f, false},
      // Water's F0 (0.33 / 2.33)^2; ior 1 with the default specular: F0 0.
      {{{"KHR_materials_ior", {{"ior", 1.33}}}}, 0.0, glm::vec3(0.0200593f), 1.0f, false},
      {{{"KHR_materials_ior", {{"ior", 1.0}}}}, 0.0, glm::vec3(0.0f), 1.0f, false},
      // A tinted, half-strength specular layer.
      {{{"KHR_materials_specular",
         {{"specularColorFactor", {1.0, 0.5, 0.25}}, {"specularFactor", 0.5}}}},
       0.0,
       glm::vec3(0.02f, 0.01f, 0.005f),
       0.5f,
       false},
      // ior 4 with a strong tint: F0 is at most 1 before the factor.
      {{{"KHR_materials_ior", {{"ior", 4.0}}},
        {"KHR_materials_specular", {{"specularColorFactor", {3.0, 1.0, 1.0}}}}},
       0.0,
       glm::vec3(1.0f, 0.36f, 0.36f),
       1.0f,
       false},
      // No specular layer on a metal: its F0 and F90 are the base colour
      // and 1 whatever the dielectric's; exact.
      {{{"KHR_materials_specular", {{"specularFactor", 0.0}}}}, 1.0, glm::vec3(0.0f), 0.0f, false},
      // A textured layer: the factors, not the texture.
      {{{"KHR_materials_specular", {{"specularTexture", {{"index", 0}}}}}},
       0.0,
       glm::vec3(0.04f),
       1.0f,
       true},
  };
  for (const Case& c : cases) {
    TestGltf gltf;
    const int material = gltf.AddMaterial(
        {{"pbrMetallicRoughness", {{"metallicFactor", c.metallic}}}, {"extensions", c.extensions}});
    gltf.AddRoot({{"mesh", AddQuadMesh(&gltf, true, material)}});
    auto scene = Import(gltf.ToGltf());
    ASSERT_TRUE(scene.ok()) << scene.status() << " " << c.extensions.dump();
    EXPECT_EQ(!scene->ignored_extensions.empty(), c.ignored) << c.extensions.dump();
    const Material& m = scene->materials[0];
    EXPECT_EQ(m.roughness_factor, 1.0f) << c.extensions.dump();  // unchanged
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.specular_f0[i], c.f0[i], 1e-6) << c.extensions.dump();
    EXPECT_FLOAT_EQ(m.specular_f90, c.f90) << c.extensions.dump();
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

// KHR_texture_transform is read: uv' = T(offset) R(rotation) S(scale) (uv,
// 1), R with rows (cos, sin), (-sin, cos), the direction the Khronos test
// model (TextureTransformTest) marks green. Offset (0.5, 0.25), a quarter
// turn, scale (2, 3): u' = 3 v + 0.5, v' = -2 u + 0.25.
TEST(GltfExtensions, TextureTransformIsRead) {
  TestGltf gltf;
  // A 1 x 1 PNG.
  gltf.doc["images"] = {
      {{"uri",
        "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8/"
        "5+hHgAHggJ/PchI7wAAAABJRU5ErkJggg=="}}};
  gltf.doc["textures"] = {{{"source", 0}}};
  const int material = gltf.AddMaterial(
      {{"emissiveTexture",
        {{"index", 0},
         {"extensions",
          {{"KHR_texture_transform",
            {{"offset", {0.5, 0.25}}, {"rotation", 1.5707963267948966}, {"scale", {2.0, 3.0}}}}}}}},
       {"emissiveFactor", {1.0, 1.0, 1.0}}});
  gltf.AddRoot({{"mesh", AddQuadMesh(&gltf, true, material)}});
  gltf.doc["extensionsUsed"] = {"KHR_texture_transform"};
  auto scene = Import(gltf.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_TRUE(scene->ignored_extensions.empty());
  const UvTransform& t = scene->materials[0].emissive_uv;
  const glm::vec2 a = t.Apply({1.0f, 0.0f}), b = t.Apply({0.0f, 1.0f});
  EXPECT_NEAR(a.x, 0.5f, 1e-6f);
  EXPECT_NEAR(a.y, -1.75f, 1e-6f);
  EXPECT_NEAR(b.x, 3.5f, 1e-6f);
  EXPECT_NEAR(b.y, 0.25f, 1e-6f);
  // Out of range: named.
  gltf.doc["materials"][0]["emissiveTexture"]["extensions"]["KHR_texture_transform"]["scale"] = {
      2e7, 1.0};
  auto huge = Import(gltf.ToGltf());
  ASSERT_FALSE(huge.ok());
  EXPECT_NE(std::string(huge.status().message())
                .find("materials[0].emissiveTexture.extensions.KHR_texture_transform.scale[0]"),
            std::string::npos)
      << huge.status();
}

// A texture's sampler (glTF 2.0 5.26) reaches its material reference:
// wrap per axis and the filters, as the file gives them; no sampler:
// repeat and the renderer's filters. A value outside the enums is refused
// naming the field, on a sampler no material uses too.
TEST(GltfExtensions, TextureSamplerIsRead) {
  TestGltf gltf;
  gltf.doc["images"] = {
      {{"uri",
        "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8/"
        "5+hHgAHggJ/PchI7wAAAABJRU5ErkJggg=="}}};
  gltf.doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}},
                          {{"minFilter", 9728}}};
  gltf.doc["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 0}}};
  const int material =
      gltf.AddMaterial({{"emissiveTexture", {{"index", 0}}},
                        {"emissiveFactor", {1.0, 1.0, 1.0}},
                        {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}});
  gltf.AddRoot({{"mesh", AddQuadMesh(&gltf, true, material)}});
  auto scene = Import(gltf.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  const TextureSampler& e = scene->materials[0].emissive_sampler;
  EXPECT_EQ(e.wrap_s, TextureSampler::kClampToEdge);
  EXPECT_EQ(e.wrap_t, TextureSampler::kMirroredRepeat);
  EXPECT_EQ(e.mag_filter, TextureSampler::kNearest);
  EXPECT_EQ(e.min_filter, 0);
  EXPECT_EQ(scene->materials[0].base_color_sampler, TextureSampler{});

  gltf.doc["samplers"][0]["wrapS"] = 12345;
  auto bad = Import(gltf.ToGltf());
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(std::string(bad.status().message()).find("samplers[0].wrapS: 12345"), std::string::npos)
      << bad.status();
  gltf.doc["samplers"][0]["wrapS"] = 10497;
  gltf.doc["samplers"][1]["minFilter"] = 9999;
  gltf.doc["textures"][1].erase("sampler");
  gltf.doc["textures"].push_back({{"source", 0}, {"sampler", 1}});  // unused texture
  auto unused = Import(gltf.ToGltf());
  ASSERT_FALSE(unused.ok());
  EXPECT_NE(std::string(unused.status().message()).find("samplers[1].minFilter: 9999"),
            std::string::npos)
      << unused.status();
  gltf.doc["samplers"][1]["minFilter"] = "linear";  // a wrong type
  auto typed = Import(gltf.ToGltf());
  ASSERT_FALSE(typed.ok());
  EXPECT_NE(std::string(typed.status().message()).find("samplers[1].minFilter"), std::string::npos)
      << typed.status();
}

}  // namespace gltf_extensions_test
}  // namespace gistream::testing
