// Skins and morph targets: import (validated, JSON paths named) and the one
// CPU deformation function (scene/state/deform.h) against hand-computed
// vertices. Tolerance: 1e-5 absolute per component.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "gltf_test_util.h"
#include "scene/state/deform.h"

namespace gistream {
namespace skin_import_test {

using testing::AddQuadMesh;
using testing::Import;
using testing::TestGltf;

constexpr float kTol = 1e-5f;
constexpr int kFloat = 5126;
constexpr int kUShort = 5123;

void ExpectVec(const glm::vec3& got, const glm::vec3& want, const std::string& what) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], kTol) << what << " component " << i;
}

// ------------------------------------------------------------------ import

int AddFloats(TestGltf* g, const std::vector<float>& v, const std::string& type, int n) {
  return g->AddAccessor(g->AddView(v.data(), v.size() * 4), kFloat, v.size() / size_t(n), type);
}

// The quad (4 vertices) skinned to two joints (nodes 1 and 2, children of
// the mesh node's sibling root), joint 1 with an inverse bind matrix that
// translates by (0, -1, 0).
TestGltf Skinned() {
  TestGltf g;
  const int mesh = AddQuadMesh(&g);
  const std::vector<uint16_t> joints = {0,      1, 0, 0, /**/ 0, 1, 0, 0, /**/ 1, 0, 0, 0,
                                        /**/ 0, 0, 0, 0};
  const int j = g.AddAccessor(g.AddView(joints.data(), joints.size() * 2), kUShort, 4, "VEC4");
  // Vertex 0 sums to 2 (renormalised to 0.5 / 0.5).
  const int w = AddFloats(&g, {1, 1, 0, 0, /**/ 0.5f, 0.5f, 0, 0, /**/ 1, 0, 0, 0, /**/ 1, 0, 0, 0},
                          "VEC4", 4);
  auto& attributes = g.doc["meshes"][size_t(mesh)]["primitives"][0]["attributes"];
  attributes["JOINTS_0"] = j;
  attributes["WEIGHTS_0"] = w;
  const int ibm = AddFloats(&g, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,  0, 1,  //
                                 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1},
                            "MAT4", 16);
  g.AddRoot({{"mesh", mesh}, {"skin", 0}});
  const int j1 = g.AddNode({{"name", "bone1"}, {"translation", {0, 1, 0}}});
  g.AddRoot({{"name", "bone0"}, {"children", {j1}}});
  // Nodes: 0 mesh, 1 bone1, 2 bone0 (the skeleton root).
  g.doc["skins"] = {{{"joints", {2, 1}}, {"inverseBindMatrices", ibm}, {"skeleton", 2}}};
  return g;
}

TEST(SkinImport, ImportsSkinsJointsAndRenormalisedWeights) {
  absl::StatusOr<Scene> scene = Import(Skinned().ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  ASSERT_EQ(scene->skins.size(), 1u);
  const Skin& skin = scene->skins[0];
  EXPECT_EQ(skin.joints, (std::vector<int>{2, 1}));
  EXPECT_EQ(skin.skeleton, 2);
  EXPECT_EQ(skin.inverse_bind_matrices[0], glm::mat4(1.0f));
  EXPECT_EQ(skin.inverse_bind_matrices[1], glm::translate(glm::mat4(1.0f), {0, -1, 0}));
  EXPECT_EQ(scene->nodes[0].skin, 0);
  const Primitive& p = scene->meshes[0].primitives[0];
  ASSERT_EQ(p.joints.size(), 4u);
  EXPECT_EQ(p.joints[2], glm::u16vec4(1, 0, 0, 0));
  EXPECT_NEAR(p.weights[0].x, 0.5f, kTol);
  EXPECT_NEAR(p.weights[0].y, 0.5f, kTol);
}

TEST(SkinImport, InverseBindMatricesDefaultToIdentity) {
  TestGltf g = Skinned();
  g.doc["skins"][0].erase("inverseBindMatrices");
  absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  for (const glm::mat4& m : scene->skins[0].inverse_bind_matrices) EXPECT_EQ(m, glm::mat4(1.0f));
}

TEST(SkinImport, InvalidSkinsNameTheirJsonPath) {
  TestGltf g = Skinned();
  auto& attributes = g.doc["meshes"][0]["primitives"][0]["attributes"];
  attributes["WEIGHTS_0"] =
      AddFloats(&g, {1, 0, 0, 0, 1, 0, 0, 0, 1, -0.5f, 0, 0, 1, 0, 0, 0}, "VEC4", 4);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].attributes.WEIGHTS_0: vertex 2 has negative weight -0.5");

  g = Skinned();
  g.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] =
      AddFloats(&g, {1, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4", 4);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].attributes.WEIGHTS_0: vertex 1 has all-zero weights");

  g = Skinned();
  g.doc["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].attributes.WEIGHTS_0: missing");

  g = Skinned();
  g.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] =
      AddFloats(&g, {1, 0, 0, 0, 1, 0, 0, 0}, "VEC4", 4);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].attributes.WEIGHTS_0: 2 elements but POSITION has 4");

  g = Skinned();
  g.doc["skins"][0]["joints"] = {2};  // vertex 0 names joint 1
  g.doc["skins"][0].erase("inverseBindMatrices");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].attributes.JOINTS_0: vertex 0 names joint 1 but "
               "nodes[0].skin (skins[0]) has 1 joints");

  g = Skinned();
  g.doc["skins"][0]["joints"] = {2, 9};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "skins[0].joints[1]: 9 is out of range (3 nodes)");

  g = Skinned();
  g.doc["skins"][0]["joints"] = {2, 2};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "skins[0].joints[1]: node 2 is listed twice");

  g = Skinned();
  g.doc["skins"][0]["skeleton"] = 5;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "skins[0].skeleton: 5 is out of range");

  g = Skinned();
  g.doc["nodes"][0]["skin"] = 1;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].skin: 1 is out of range (1 skins)");

  g = Skinned();
  g.doc["skins"][0]["inverseBindMatrices"] =
      AddFloats(&g, std::vector<float>(16, 0.0f), "MAT4", 16);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "skins[0].inverseBindMatrices: 1 matrices for 2 joints");

  g = Skinned();
  std::vector<float> singular(32, 0.0f);
  singular[15] = singular[31] = 1.0f;
  g.doc["skins"][0]["inverseBindMatrices"] = AddFloats(&g, singular, "MAT4", 16);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "skins[0].inverseBindMatrices: matrix 0 is singular");

  // Issue 30: a scale of 1e30 (finite, non-singular) would move skinned
  // vertices far past the coordinate limit; a node's scale limits hold.
  g = Skinned();
  std::vector<float> huge = {1e30f, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,  //
                             1,     0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  g.doc["skins"][0]["inverseBindMatrices"] = AddFloats(&g, huge, "MAT4", 16);
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "skins[0].inverseBindMatrices matrix 0 scale.x: 1e+30 is out of range");
  huge[0] = 1e6f;  // the largest scale a node may have
  g.doc["skins"][0]["inverseBindMatrices"] = AddFloats(&g, huge, "MAT4", 16);
  EXPECT_TRUE(Import(g.ToGltf()).ok());
}

TEST(MorphImport, ImportsTargetsAndDefaultWeights) {
  TestGltf g;
  const int mesh = AddQuadMesh(&g);
  const int d0 = g.AddVec3({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  const int d1 = g.AddVec3({1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  g.doc["meshes"][size_t(mesh)]["primitives"][0]["targets"] = {{{"POSITION", d0}},
                                                               {{"POSITION", d1}}};
  g.doc["meshes"][size_t(mesh)]["weights"] = {0.25, 0.0};
  g.AddRoot({{"mesh", mesh}, {"weights", {1.0, 0.5}}});
  absl::StatusOr<Scene> scene = Import(g.ToGltf());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_EQ(scene->meshes[0].weights, (std::vector<float>{0.25f, 0.0f}));
  EXPECT_EQ(scene->nodes[0].weights, (std::vector<float>{1.0f, 0.5f}));
  ASSERT_EQ(scene->meshes[0].primitives[0].targets.size(), 2u);
  EXPECT_EQ(scene->meshes[0].primitives[0].targets[1].positions[0], glm::vec3(1, 0, 0));
  EXPECT_TRUE(scene->meshes[0].primitives[0].targets[1].normals.empty());
}

TEST(MorphImport, InvalidTargetsNameTheirJsonPath) {
  TestGltf g;
  const int mesh = AddQuadMesh(&g);
  const int d0 = g.AddVec3({0, 0, 1, 0, 0, 1, 0, 0, 1});  // 3 deltas for 4 vertices
  g.doc["meshes"][size_t(mesh)]["primitives"][0]["targets"] = {{{"POSITION", d0}}};
  g.AddRoot({{"mesh", mesh}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].targets[0].POSITION: 3 elements but POSITION has 4");

  const int d1 = g.AddVec3({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  g.doc["meshes"][size_t(mesh)]["primitives"][0]["targets"] = {{{"POSITION", d1}}};
  g.doc["meshes"][size_t(mesh)]["weights"] = {0.5, 0.5};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].weights: 2 weights but the mesh has 1 morph targets");

  g.doc["meshes"][size_t(mesh)].erase("weights");
  g.doc["nodes"][0]["weights"] = {0.5, 0.5};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "nodes[0].weights: 2 weights but its mesh has 1 morph targets");

  // Issue 30: each delta within the coordinate limit (8e5 m), but at the
  // largest accepted weight (100) a vertex would reach 8e7 m.
  g.doc["nodes"][0].erase("weights");
  const int far = g.AddVec3({0, 0, 8e5f, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  g.doc["meshes"][size_t(mesh)]["primitives"][0]["targets"] = {{{"POSITION", far}}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].targets: vertex 0 reaches 8e+07 m at morph weights of "
               "+-100");
  const int near = g.AddVec3({0, 0, 9e3f, 0, 0, 0, 0, 0, 0, 0, 0, 0});  // 9e5 m at 100
  g.doc["meshes"][size_t(mesh)]["primitives"][0]["targets"] = {{{"POSITION", near}}};
  EXPECT_TRUE(Import(g.ToGltf()).ok());

  g.doc["meshes"][size_t(mesh)]["primitives"][0]["targets"] = {{{"POSITION", d1}}};
  g.doc["meshes"][size_t(mesh)]["primitives"][0]["targets"][0]["NORMAL"] = "x";
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].targets[0].NORMAL: \"x\" is not an index");
}

// ------------------------------------------------------------------ deform

// Four vertices on the x axis and above it, all facing +X.
Primitive Strip() {
  Primitive p;
  p.positions = {{1, 0, 0}, {1, 1, 0}, {2, 0, 0}, {0, 0, 3}};
  p.normals.assign(4, glm::vec3(1, 0, 0));
  p.indices = {0, 1, 2, 0, 2, 3};
  return p;
}

TEST(Deform, IdentityJointLeavesVerticesUnchanged) {
  Primitive p = Strip();
  p.joints.assign(4, glm::u16vec4(0, 0, 0, 0));
  p.weights.assign(4, glm::vec4(1, 0, 0, 0));
  const glm::mat4 identity(1.0f);
  std::vector<glm::vec3> pos, nrm;
  DeformPrimitive(p, {}, std::span(&identity, 1), &pos, &nrm);
  for (size_t i = 0; i < 4; ++i) {
    ExpectVec(pos[i], p.positions[i], "position");
    ExpectVec(nrm[i], p.normals[i], "normal");
  }
}

TEST(Deform, OneJointTranslatedThroughTheNodeHierarchy) {
  // Node 0: the mesh node, at (5, 0, 0) (not part of skinning); node 1: a
  // joint translated by (1, 2, 3); bind pose at the origin (IBM identity).
  Scene scene;
  scene.nodes.resize(2);
  scene.nodes[0].translation = {5, 0, 0};
  scene.nodes[1].translation = {1, 2, 3};
  Skin skin;
  skin.joints = {1};
  skin.inverse_bind_matrices = {glm::mat4(1.0f)};
  const std::vector<glm::mat4> world = WorldMatrices(scene, scene.nodes);
  const std::vector<glm::mat4> joints = JointMatrices(skin, world, 0);
  Primitive p = Strip();
  p.joints.assign(4, glm::u16vec4(0));
  p.weights.assign(4, glm::vec4(1, 0, 0, 0));
  std::vector<glm::vec3> pos, nrm;
  DeformPrimitive(p, {}, joints, &pos, &nrm);
  // Mesh-local result: joint world (1, 2, 3) minus the mesh node's (5, 0, 0).
  for (size_t i = 0; i < 4; ++i) {
    ExpectVec(pos[i], p.positions[i] + glm::vec3(-4, 2, 3), "position");
    ExpectVec(nrm[i], {1, 0, 0}, "normal");
  }
}

TEST(Deform, TwoJointsHalfAndHalf) {
  // Joint 0 identity; joint 1 rotated 90 degrees about +Z about the bind
  // position (0, 1, 0): J1 = T(0, 1, 0) R_z(90) IBM with IBM = T(0, -1, 0).
  const glm::mat4 rot = glm::rotate(glm::mat4(1.0f), 1.5707963f, glm::vec3(0, 0, 1));
  const glm::mat4 j1 = glm::translate(glm::mat4(1.0f), {0, 1, 0}) * rot *
                       glm::translate(glm::mat4(1.0f), {0, -1, 0});
  const std::vector<glm::mat4> joints = {glm::mat4(1.0f), j1};
  Primitive p;
  p.positions = {{1, 1, 0}, {1, 0, 0}};
  p.normals = {{1, 0, 0}, {0, 0, 1}};
  p.joints = {glm::u16vec4(1, 0, 0, 0), glm::u16vec4(0, 1, 0, 0)};
  p.weights = {glm::vec4(1, 0, 0, 0), glm::vec4(0.5f, 0.5f, 0, 0)};
  std::vector<glm::vec3> pos, nrm;
  DeformPrimitive(p, {}, joints, &pos, &nrm);
  // Vertex 0 fully on joint 1: (1, 1) -> (1, 0) about the bind point ->
  // rotated to (0, 1) -> (0, 2, 0); its normal +X turns to +Y.
  ExpectVec(pos[0], {0, 2, 0}, "vertex 0");
  ExpectVec(nrm[0], {0, 1, 0}, "normal 0");
  // Vertex 1 half/half: joint 0 leaves (1, 0, 0); joint 1 maps it to
  // (1, -1) -> (1, -1) rotated = (1, 1) -> (1, 2, 0); the mean is (1, 1, 0).
  ExpectVec(pos[1], {1, 1, 0}, "vertex 1");
  ExpectVec(nrm[1], {0, 0, 1}, "normal 1");  // +Z is fixed by a rotation about Z
}

TEST(Deform, MorphWeightsAddWeightedDeltas) {
  Primitive p = Strip();
  p.targets.resize(2);
  p.targets[0].positions = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  p.targets[1].positions = {{1, 0, 0}, {0, 0, 0}, {0, 2, 0}, {0, 0, 0}};
  p.targets[1].normals = {{-1, 1, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  const std::vector<float> weights = {0.5f, -1.0f};
  std::vector<glm::vec3> pos, nrm;
  DeformPrimitive(p, weights, {}, &pos, &nrm);
  // p + 0.5 dP0 - dP1.
  ExpectVec(pos[0], {0, 0, 0.5f}, "vertex 0");
  ExpectVec(pos[1], {1, 1, 0.5f}, "vertex 1");
  ExpectVec(pos[2], {2, -2, 0.5f}, "vertex 2");
  ExpectVec(pos[3], {0, 0, 3.5f}, "vertex 3");
  // n - dN1 = (2, -1, 0), normalised.
  ExpectVec(nrm[0], glm::vec3(2, -1, 0) / std::sqrt(5.0f), "normal 0");
  ExpectVec(nrm[1], {1, 0, 0}, "normal 1");
}

TEST(Deform, MorphThenSkinAndNodeWeightsOverrideTheMesh) {
  Scene scene;
  scene.meshes.resize(1);
  scene.meshes[0].weights = {0.0f};
  scene.nodes.resize(1);
  scene.nodes[0].mesh = 0;
  EXPECT_EQ(MorphWeights(scene, scene.nodes[0]).size(), 1u);
  EXPECT_EQ(MorphWeights(scene, scene.nodes[0])[0], 0.0f);
  scene.nodes[0].weights = {1.0f};
  EXPECT_EQ(MorphWeights(scene, scene.nodes[0])[0], 1.0f);

  Primitive p;
  p.positions = {{1, 0, 0}};
  p.normals = {{0, 0, 1}};
  p.targets.resize(1);
  p.targets[0].positions = {{0, 1, 0}};
  p.joints = {glm::u16vec4(0)};
  p.weights = {glm::vec4(1, 0, 0, 0)};
  const glm::mat4 j = glm::translate(glm::mat4(1.0f), {0, 0, 2});
  std::vector<glm::vec3> pos, nrm;
  DeformPrimitive(p, MorphWeights(scene, scene.nodes[0]), std::span(&j, 1), &pos, &nrm);
  ExpectVec(pos[0], {1, 1, 2}, "morphed then translated");
}

}  // namespace skin_import_test
}  // namespace gistream
