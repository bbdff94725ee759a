// Import of well-formed glTF: counts, hierarchy, transforms, materials,
// lights, cameras.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "encode/encode.h"
#include "gltf_test_util.h"
#include "scene/gltf/gltf_import.h"

namespace gistream {
namespace scene_import_test {

using testing::AddQuadMesh;
using testing::Import;
using testing::TestGltf;

constexpr float kEps = 1e-5f;

void ExpectVec3(const glm::vec3& a, const glm::vec3& b, float eps = kEps) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

// A parent translated to (0, 0, 5) holding a child at (1, 0, 0) with the quad.
TestGltf ParentChildQuad() {
  TestGltf g;
  const int mesh = AddQuadMesh(&g);
  const int child = g.AddNode({{"name", "child"}, {"mesh", mesh}, {"translation", {1, 0, 0}}});
  g.AddRoot({{"name", "parent"}, {"translation", {0, 0, 5}}, {"children", {child}}});
  return g;
}

void ExpectParentChildQuad(const Scene& scene) {
  ASSERT_EQ(scene.nodes.size(), 2u);
  EXPECT_EQ(scene.roots, std::vector<int>{1});
  EXPECT_EQ(scene.nodes[0].name, "child");
  EXPECT_EQ(scene.nodes[0].parent, 1);
  EXPECT_EQ(scene.nodes[1].children, std::vector<int>{0});
  EXPECT_EQ(scene.triangle_count, 2u);
  EXPECT_EQ(scene.vertex_count, 4u);
  ASSERT_EQ(scene.meshes.size(), 1u);
  ASSERT_EQ(scene.meshes[0].primitives.size(), 1u);
  EXPECT_EQ(scene.meshes[0].primitives[0].indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  const std::vector<glm::mat4> world = WorldMatrices(scene, scene.nodes);
  ExpectVec3(glm::vec3(world[0][3]), {1, 0, 5});
  ExpectVec3(scene.bounds.min, {0, -1, 5});
  ExpectVec3(scene.bounds.max, {2, 1, 5});
}

TEST(SceneImport, GltfWithChildUnderTranslatedParent) {
  const absl::StatusOr<Scene> scene = Import(ParentChildQuad().ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ExpectParentChildQuad(*scene);
}

TEST(SceneImport, GlbGivesTheSameScene) {
  const absl::StatusOr<Scene> scene = Import(ParentChildQuad().ToGlb());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ExpectParentChildQuad(*scene);
}

TEST(SceneImport, NameComesFromOptions) {
  ImportOptions options;
  options.name = "quad";
  EXPECT_EQ(Import(ParentChildQuad().ToGltf(), options)->name, "quad");
}

TEST(SceneImport, CountsAreOverInstances) {
  TestGltf g;
  const int mesh = AddQuadMesh(&g);
  g.AddRoot({{"mesh", mesh}});
  g.AddRoot({{"mesh", mesh}, {"translation", {10, 0, 0}}});
  g.AddNode({{"mesh", mesh}});  // not in the default scene: not counted
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_EQ(scene->triangle_count, 4u);
  EXPECT_EQ(scene->vertex_count, 8u);
  ExpectVec3(scene->bounds.min, {-1, -1, 0});
  ExpectVec3(scene->bounds.max, {11, 1, 0});
}

TEST(SceneImport, WithoutScenesEveryParentlessNodeIsARoot) {
  TestGltf g;
  const int mesh = AddQuadMesh(&g);
  g.AddNode({{"mesh", mesh}});
  g.AddNode({{"mesh", mesh}});
  g.doc.erase("scenes");
  g.doc.erase("scene");
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_EQ(scene->roots, (std::vector<int>{0, 1}));
  EXPECT_EQ(scene->triangle_count, 4u);
}

TEST(SceneImport, MatrixIsDecomposedIntoTrs) {
  TestGltf g;
  const int mesh = AddQuadMesh(&g);
  // Scale 2, then 90 degrees about +Y, then translate (1, 2, 3).
  const glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(1, 2, 3)) *
                      glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 1, 0)) *
                      glm::scale(glm::mat4(1.0f), glm::vec3(2.0f));
  std::vector<float> values(&m[0][0], &m[0][0] + 16);
  g.AddRoot({{"mesh", mesh}, {"matrix", values}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  const Node& n = scene->nodes[0];
  ExpectVec3(n.translation, {1, 2, 3});
  ExpectVec3(n.scale, {2, 2, 2});
  const glm::mat4 back = LocalMatrix(n);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(back[c][r], m[c][r], 1e-5f) << c << "," << r;
  }
}

TEST(SceneImport, MirrorMatrixKeepsItsHandedness) {
  TestGltf g;
  const int mesh = AddQuadMesh(&g);
  g.AddRoot({{"mesh", mesh}, {"matrix", {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  const glm::mat4 back = LocalMatrix(scene->nodes[0]);
  EXPECT_NEAR(glm::determinant(back), -1.0f, 1e-5f);
  ExpectVec3(glm::vec3(back * glm::vec4(1, 0, 0, 0)), {-1, 0, 0});
}

TEST(SceneImport, NearUnitRotationIsNormalized) {
  TestGltf g;
  g.AddRoot({{"rotation", {0, 0, 0, 1.005}}});  // within the 1e-2 tolerance
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_NEAR(scene->nodes[0].rotation.w, 1.0f, kEps);
}

TEST(SceneImport, FarFromUnitRotationIsRejected) {
  TestGltf g;
  g.AddRoot({{"rotation", {0, 0, 0, 2}}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].rotation: length 2 is not 1");
}

TEST(SceneImport, NonIndexedPrimitiveBecomesIndexed) {
  TestGltf g;
  const int pos = g.AddVec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int mesh = g.AddMesh({{"attributes", {{"POSITION", pos}}}});
  g.AddRoot({{"mesh", mesh}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  const Primitive& p = scene->meshes[0].primitives[0];
  EXPECT_EQ(p.indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(p.normals.size(), 3u);
  EXPECT_TRUE(p.uvs.empty());
  EXPECT_EQ(scene->triangle_count, 1u);
}

TEST(SceneImport, MissingNormalsAreGeneratedFacingTheWinding) {
  for (const bool flip : {false, true}) {
    TestGltf g;
    const int pos = g.AddVec3({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0});
    const std::vector<uint16_t> ccw = {0, 1, 2, 0, 2, 3};
    const std::vector<uint16_t> cw = {0, 2, 1, 0, 3, 2};
    const int idx = g.AddIndices16(flip ? cw : ccw);
    const int mesh = g.AddMesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}});
    g.AddRoot({{"mesh", mesh}});
    const absl::StatusOr<Scene> scene = Import(g.ToGltf());
    ASSERT_TRUE(scene.ok()) << scene.status();
    const Primitive& p = scene->meshes[0].primitives[0];
    ASSERT_EQ(p.normals.size(), p.positions.size());
    EXPECT_EQ(p.positions.size(), 4u);  // a flat quad needs no split vertices
    for (const glm::vec3& n : p.normals) {
      EXPECT_NEAR(glm::length(n), 1.0f, kEps);
      ExpectVec3(n, {0, 0, flip ? -1.0f : 1.0f});
    }
  }
}

TEST(SceneImport, FileNormalsAreNormalized) {
  TestGltf g;
  const int pos = g.AddVec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int nrm = g.AddVec3({0, 0, 2, 0, 0, 3, 0, 0, 0.5f});
  const int mesh = g.AddMesh({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}});
  g.AddRoot({{"mesh", mesh}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  for (const glm::vec3& n : scene->meshes[0].primitives[0].normals) ExpectVec3(n, {0, 0, 1});
}

TEST(SceneImport, TexcoordsFloatAndNormalizedBytes) {
  TestGltf g;
  const int pos = g.AddVec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const uint8_t uv8[] = {0, 0, 255, 0, 0, 255};
  const int uv_view = g.AddView(uv8, sizeof(uv8));
  const int uv = g.AddAccessor(uv_view, 5121, 3, "VEC2");
  g.doc["accessors"][size_t(uv)]["normalized"] = true;
  const int mesh = g.AddMesh({{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}});
  g.AddRoot({{"mesh", mesh}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  const std::vector<glm::vec2>& uvs = scene->meshes[0].primitives[0].uvs;
  ASSERT_EQ(uvs.size(), 3u);
  EXPECT_EQ(uvs[1], glm::vec2(1, 0));
  EXPECT_EQ(uvs[2], glm::vec2(0, 1));
}

TEST(SceneImport, InterleavedAttributesWithStride) {
  TestGltf g;
  // position xyz + normal xyz per vertex, 24-byte stride.
  const float data[] = {0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1};
  const int view = g.AddView(data, sizeof(data), 24);
  const int pos = g.AddAccessor(view, 5126, 3, "VEC3");
  const int nrm = g.AddAccessor(view, 5126, 3, "VEC3", 12);
  const int mesh = g.AddMesh({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}});
  g.AddRoot({{"mesh", mesh}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  const Primitive& p = scene->meshes[0].primitives[0];
  EXPECT_EQ(p.positions[2], glm::vec3(0, 1, 0));
  EXPECT_EQ(p.normals[1], glm::vec3(0, 0, 1));
}

TEST(SceneImport, SeveralPrimitivesAndSkippedLines) {
  TestGltf g;
  const int pos = g.AddVec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int mat = g.AddMaterial({{"name", "m"}});
  g.doc["meshes"].push_back(
      {{"primitives",
        {{{"attributes", {{"POSITION", pos}}}, {"material", mat}},
         {{"attributes", {{"POSITION", pos}}}, {"mode", 1}},  // lines: skipped
         {{"attributes", {{"POSITION", pos}}}, {"mode", 4}}}}});
  g.AddRoot({{"mesh", 0}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ASSERT_EQ(scene->meshes[0].primitives.size(), 2u);
  EXPECT_EQ(scene->meshes[0].primitives[0].material, 0);
  EXPECT_EQ(scene->meshes[0].primitives[1].material, -1);
  EXPECT_EQ(scene->triangle_count, 2u);
}

// Triangle strips and fans (glTF modes 5 and 6; the Khronos asset
// generator's Mesh_PrimitiveMode files, refused before) import as the
// triangle lists they draw, with the first triangle's winding (glTF 2.0
// Sec. 3.7.2.1), degenerate strip joins left out.
TEST(SceneImport, StripsAndFansBecomeTriangleLists) {
  TestGltf g;
  // A unit square's corners: 0 (0,0) 1 (1,0) 2 (0,1) 3 (1,1).
  const int pos = g.AddVec3({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  const uint16_t strip[] = {0, 1, 2, 3, 3};  // the last repeats: one degenerate triangle
  const int strip_indices = g.AddAccessor(g.AddView(strip, sizeof(strip)), 5123, 5, "SCALAR");
  const uint16_t fan[] = {0, 1, 3, 2};
  const int fan_indices = g.AddAccessor(g.AddView(fan, sizeof(fan)), 5123, 4, "SCALAR");
  g.doc["meshes"].push_back(
      {{"primitives",
        {{{"attributes", {{"POSITION", pos}}}, {"indices", strip_indices}, {"mode", 5}},
         {{"attributes", {{"POSITION", pos}}}, {"indices", fan_indices}, {"mode", 6}},
         {{"attributes", {{"POSITION", pos}}}, {"mode", 5}}}}});  // no indices: 0 1 2 3
  g.AddRoot({{"mesh", 0}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  const std::vector<Primitive>& p = scene->meshes[0].primitives;
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0].indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(p[1].indices, (std::vector<uint32_t>{1, 3, 0, 3, 2, 0}));
  EXPECT_EQ(p[2].indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(scene->triangle_count, 6u);
  // Every triangle faces +Z, as the first (counter-clockwise from +Z).
  for (const Primitive& prim : p) {
    for (size_t t = 0; t < prim.indices.size(); t += 3) {
      const glm::vec3 a = prim.positions[prim.indices[t]], b = prim.positions[prim.indices[t + 1]],
                      c = prim.positions[prim.indices[t + 2]];
      EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f) << t;
    }
  }
}

TEST(SceneImport, Materials) {
  TestGltf g;
  const int mat = g.AddMaterial(
      {{"name", "lamp"},
       {"pbrMetallicRoughness",
        {{"baseColorFactor", {0.5, 0.25, 0.125, 1}},
         {"metallicFactor", 0},
         {"roughnessFactor", 0.5}}},
       {"emissiveFactor", {1, 0.5, 0}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 20}}}}},
       {"doubleSided", true}});
  g.AddRoot({{"mesh", AddQuadMesh(&g, true, mat)}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ASSERT_EQ(scene->materials.size(), 1u);
  const Material& m = scene->materials[0];
  EXPECT_EQ(m.name, "lamp");
  EXPECT_EQ(m.base_color_factor, glm::vec4(0.5f, 0.25f, 0.125f, 1.0f));
  EXPECT_EQ(m.metallic_factor, 0.0f);
  EXPECT_EQ(m.roughness_factor, 0.5f);
  EXPECT_TRUE(m.double_sided);
  EXPECT_TRUE(m.emissive());
  ExpectVec3(m.emission(), {20, 10, 0});
  EXPECT_EQ(m.base_color_texture, -1);
  EXPECT_EQ(scene->meshes[0].primitives[0].material, 0);
}

TEST(SceneImport, TexturesAreDecodedOncePerImage) {
  TestGltf g;
  const std::vector<uint8_t> rgba = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 9, 9, 9, 128};
  const absl::StatusOr<std::string> png = EncodePng(rgba, 2, 2);
  ASSERT_TRUE(png.ok());
  const int view = g.AddView(png->data(), png->size());
  g.doc["images"] = {{{"bufferView", view}, {"mimeType", "image/png"}, {"name", "checker"}}};
  g.doc["textures"] = {{{"source", 0}}};
  const int mat = g.AddMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
                                 {"emissiveTexture", {{"index", 0}}}});
  g.AddRoot({{"mesh", AddQuadMesh(&g, true, mat)}});
  for (const std::vector<uint8_t>& bytes : {g.ToGltf(), g.ToGlb()}) {
    const absl::StatusOr<Scene> scene = Import(bytes);
    ASSERT_TRUE(scene.ok()) << scene.status();
    ASSERT_EQ(scene->images.size(), 1u);
    const Image& image = scene->images[0];
    EXPECT_EQ(image.name, "checker");
    EXPECT_EQ(image.width, 2);
    EXPECT_EQ(image.height, 2);
    EXPECT_TRUE(image.srgb);
    EXPECT_FALSE(image.is_float);
    EXPECT_EQ(image.pixels8, rgba);
    EXPECT_EQ(scene->materials[0].base_color_texture, 0);
    EXPECT_EQ(scene->materials[0].emissive_texture, 0);
  }
}

TEST(SceneImport, DataUriImage) {
  TestGltf g;
  const std::vector<uint8_t> rgba(4 * 4 * 4, 200);
  const absl::StatusOr<std::string> png = EncodePng(rgba, 4, 4);
  ASSERT_TRUE(png.ok());
  g.doc["images"] = {{{"uri", "data:image/png;base64," + testing::Base64(std::vector<uint8_t>(
                                                             png->begin(), png->end()))}}};
  g.doc["textures"] = {{{"source", 0}}};
  const int mat = g.AddMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  g.AddRoot({{"mesh", AddQuadMesh(&g, true, mat)}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ASSERT_EQ(scene->images.size(), 1u);
  EXPECT_EQ(scene->images[0].pixels8, rgba);
}

TEST(SceneImport, PunctualLights) {
  TestGltf g;
  g.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  g.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 100}, {"name", "bulb"}},
      {{"type", "spot"},
       {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.5}}},
       {"range", 20}},
      {{"type", "directional"}, {"intensity", 3}}};
  g.AddRoot({{"name", "sun"}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  g.AddRoot({{"name", "bulb"},
             {"translation", {0, 3, 0}},
             {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  g.AddRoot({{"name", "spot"}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ASSERT_EQ(scene->lights.size(), 3u);
  EXPECT_EQ(scene->lights[0].type, LightType::kPoint);
  EXPECT_EQ(scene->lights[0].name, "bulb");
  EXPECT_EQ(scene->lights[0].intensity, 100.0f);
  ExpectVec3(scene->lights[0].color, {1, 0.5f, 0.25f});
  EXPECT_EQ(scene->lights[1].type, LightType::kSpot);
  EXPECT_FLOAT_EQ(scene->lights[1].inner_cone_angle, 0.1f);
  EXPECT_FLOAT_EQ(scene->lights[1].outer_cone_angle, 0.5f);
  EXPECT_EQ(scene->lights[1].range, 20.0f);
  EXPECT_EQ(scene->lights[2].type, LightType::kDirectional);
  EXPECT_EQ(LightInstanceNodes(*scene), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(scene->nodes[0].light, 2);
  EXPECT_EQ(scene->nodes[1].light, 0);
}

TEST(SceneImport, PerspectiveCamerasAndSkippedOrthographic) {
  TestGltf g;
  g.doc["cameras"] = {{{"type", "orthographic"},
                       {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}},
                      {{"type", "perspective"},
                       {"name", "main"},
                       {"perspective", {{"yfov", 0.7}, {"znear", 0.05}, {"zfar", 100}}}}};
  g.AddRoot({{"name", "ortho"}, {"camera", 0}});
  g.AddRoot({{"name", "camera"}, {"camera", 1}, {"translation", {0, 1, 5}}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ASSERT_EQ(scene->cameras.size(), 1u);
  EXPECT_EQ(scene->cameras[0].name, "main");
  EXPECT_FLOAT_EQ(scene->cameras[0].yfov, 0.7f);
  EXPECT_FLOAT_EQ(scene->cameras[0].znear, 0.05f);
  EXPECT_FLOAT_EQ(scene->cameras[0].zfar, 100.0f);
  EXPECT_EQ(scene->nodes[0].camera, -1);
  EXPECT_EQ(scene->nodes[1].camera, 0);
  EXPECT_EQ(CameraInstanceNodes(*scene), std::vector<int>{1});
}

}  // namespace scene_import_test
}  // namespace gistream
