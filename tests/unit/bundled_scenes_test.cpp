// Every bundled scene imports by name and has what its README promises.
// A missing scene file fails (never skips).
#include <set>

#include <gtest/gtest.h>

#include "scene/gltf/gltf_import.h"

namespace gistream {
namespace bundled_scenes_test {

const std::string kSceneDir = std::string(GISTREAM_SOURCE_DIR "/scenes");

std::set<std::string> NodeNames(const Scene& s) {
  std::set<std::string> names;
  for (const Node& n : s.nodes) names.insert(n.name);
  return names;
}

class BundledScene : public ::testing::TestWithParam<const char*> {};

TEST_P(BundledScene, Imports) {
  auto scene = ImportSceneByName(kSceneDir, GetParam(), {});
  ASSERT_TRUE(scene.ok()) << GetParam() << ": " << scene.status();
  EXPECT_EQ(scene->name, GetParam());
  EXPECT_FALSE(scene->roots.empty());
  EXPECT_FALSE(scene->materials.empty());
  EXPECT_GT(scene->triangle_count, 0u);
  EXPECT_GT(scene->vertex_count, 0u);
  EXPECT_FALSE(scene->bounds.empty());
  EXPECT_EQ(CameraInstanceNodes(*scene).size(), 1u) << "every bundled scene has a camera";
  for (const Mesh& m : scene->meshes) {
    for (const Primitive& p : m.primitives) {
      ASSERT_EQ(p.normals.size(), p.positions.size());
      for (const glm::vec3& n : p.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-3f);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(All, BundledScene,
                         ::testing::Values("cornell_box", "cornell_box_coarse", "indirect_room",
                                           "furnace", "dynamic_block", "glossy_box", "bending_tube",
                                           "morph_blob"));

TEST(BundledScenes, GlossyBoxHasOneGlossyMaterial) {
  // Every material Lambertian (metallic 0, roughness 1) but the gold cube's.
  auto scene = ImportSceneByName(kSceneDir, "glossy_box", {});
  ASSERT_TRUE(scene.ok()) << scene.status();
  int glossy = 0;
  for (const Material& m : scene->materials) {
    if (m.name != "gold") {
      EXPECT_EQ(m.metallic_factor, 0.0f) << m.name;
      EXPECT_EQ(m.roughness_factor, 1.0f) << m.name;
      continue;
    }
    ++glossy;
    EXPECT_EQ(m.metallic_factor, 1.0f);
    EXPECT_FLOAT_EQ(m.roughness_factor, 0.3f);
  }
  EXPECT_EQ(glossy, 1);
  EXPECT_EQ(scene->lights.size(), 1u);
}

TEST(BundledScenes, CoarseCornellBoxIsTheSameBoxInOneQuadPerFace) {
  // 64 vertices like the common OBJ versions; the same measured corners,
  // nodes and materials as cornell_box.
  auto coarse = ImportSceneByName(kSceneDir, "cornell_box_coarse", {});
  auto fine = ImportSceneByName(kSceneDir, "cornell_box", {});
  ASSERT_TRUE(coarse.ok()) << coarse.status();
  ASSERT_TRUE(fine.ok()) << fine.status();
  EXPECT_EQ(coarse->vertex_count, 64u);
  EXPECT_EQ(coarse->triangle_count, 32u);
  EXPECT_EQ(NodeNames(*coarse), NodeNames(*fine));
  EXPECT_EQ(coarse->materials.size(), fine->materials.size());
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(coarse->bounds.min[k], fine->bounds.min[k], 1e-6f);
    EXPECT_NEAR(coarse->bounds.max[k], fine->bounds.max[k], 1e-6f);
  }
}

TEST(BundledScenes, CornellBoxIsLitByItsCeilingQuadOnly) {
  auto scene = ImportSceneByName(kSceneDir, "cornell_box", {});
  ASSERT_TRUE(scene.ok()) << scene.status();
  const std::set<std::string> names = NodeNames(*scene);
  for (const char* n :
       {"light", "tall_block", "short_block", "left_wall", "right_wall", "camera"}) {
    EXPECT_TRUE(names.count(n)) << n;
  }
  EXPECT_TRUE(scene->lights.empty());
  int emissive = 0;
  for (const Material& m : scene->materials) emissive += m.emissive() ? 1 : 0;
  EXPECT_EQ(emissive, 1);
  // The emissive material is the one on the node named "light".
  for (const Node& n : scene->nodes) {
    if (n.name != "light") continue;
    ASSERT_GE(n.mesh, 0);
    for (const Primitive& p : scene->meshes[size_t(n.mesh)].primitives) {
      ASSERT_GE(p.material, 0);
      EXPECT_TRUE(scene->materials[size_t(p.material)].emissive());
    }
  }
  // Walls tessellated for vertex-based solvers: a few thousand vertices.
  EXPECT_GT(scene->vertex_count, 2000u);
  EXPECT_LT(scene->vertex_count, 20000u);
}

TEST(BundledScenes, FurnaceIsUniform) {
  auto scene = ImportSceneByName(kSceneDir, "furnace", {});
  ASSERT_TRUE(scene.ok()) << scene.status();
  ASSERT_EQ(scene->materials.size(), 1u);
  EXPECT_NEAR(scene->materials[0].base_color_factor.r, 0.5f, 1e-6f);
  EXPECT_NEAR(scene->materials[0].emission().r, 1.0f, 1e-6f);
}

TEST(BundledScenes, DynamicBlockHasAMovableBlock) {
  auto scene = ImportSceneByName(kSceneDir, "dynamic_block", {});
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_TRUE(NodeNames(*scene).count("block"));
  EXPECT_EQ(LightInstanceNodes(*scene).size(), 2u);
}

TEST(BundledScenes, UnknownAndPathLikeNamesAreRefused) {
  EXPECT_EQ(ImportSceneByName(kSceneDir, "no_such_scene", {}).status().code(),
            absl::StatusCode::kNotFound);
  EXPECT_EQ(ImportSceneByName(kSceneDir, "../CMakeLists", {}).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace bundled_scenes_test
}  // namespace gistream
