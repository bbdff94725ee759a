// Scene graph helpers and normal generation.
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/gltf/mesh_normals.h"

namespace gistream {
namespace scene_test {

TEST(SceneGraph, LocalMatrixIsTranslateRotateScale) {
  Node n;
  n.translation = {1, 2, 3};
  n.rotation = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 0, 1));
  n.scale = {2, 2, 2};
  const glm::vec3 p = glm::vec3(LocalMatrix(n) * glm::vec4(1, 0, 0, 1));
  // (1,0,0) scaled to (2,0,0), rotated to (0,2,0), moved to (1,4,3).
  EXPECT_NEAR(p.x, 1.0f, 1e-5f);
  EXPECT_NEAR(p.y, 4.0f, 1e-5f);
  EXPECT_NEAR(p.z, 3.0f, 1e-5f);
}

TEST(SceneGraph, WorldMatricesComposeParentsFirstWhateverTheOrder) {
  Scene s;
  s.nodes.resize(3);
  // Child (0) listed before its parent (2), grandparent (1) in the middle.
  s.nodes[0].parent = 2;
  s.nodes[0].translation = {1, 0, 0};
  s.nodes[2].parent = 1;
  s.nodes[2].children = {0};
  s.nodes[2].scale = {2, 2, 2};
  s.nodes[1].children = {2};
  s.nodes[1].translation = {0, 0, 5};
  s.roots = {1};
  const std::vector<glm::mat4> world = WorldMatrices(s, s.nodes);
  const glm::vec3 origin = glm::vec3(world[0] * glm::vec4(0, 0, 0, 1));
  EXPECT_EQ(origin, glm::vec3(2, 0, 5));
  EXPECT_EQ(glm::vec3(world[1][3]), glm::vec3(0, 0, 5));

  // Edited copies of the nodes are what counts.
  std::vector<Node> moved = s.nodes;
  moved[1].translation = {0, 0, 0};
  EXPECT_EQ(glm::vec3(WorldMatrices(s, moved)[0][3]), glm::vec3(2, 0, 0));
}

TEST(SceneGraph, InstanceLists) {
  Scene s;
  s.nodes.resize(5);
  s.nodes[1].light = 0;
  s.nodes[4].light = 0;  // one light, two instances
  s.nodes[3].camera = 0;
  EXPECT_EQ(LightInstanceNodes(s), (std::vector<int>{1, 4}));
  EXPECT_EQ(CameraInstanceNodes(s), std::vector<int>{3});
}

// The 8 corners of the unit cube, shared by 12 outward-wound triangles.
Primitive SharedCornerCube() {
  Primitive p;
  for (int i = 0; i < 8; ++i)
    p.positions.push_back({i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1});
  p.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
               2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return p;
}

TEST(MeshNormals, CubeWithSharedCornersStaysFlat) {
  Primitive p = SharedCornerCube();
  GenerateNormals(&p);
  EXPECT_EQ(p.positions.size(), 24u);  // each corner split three ways
  ASSERT_EQ(p.normals.size(), p.positions.size());
  for (size_t t = 0; t < p.indices.size(); t += 3) {
    const glm::vec3 a = p.positions[p.indices[t]];
    const glm::vec3 face = glm::normalize(
        glm::cross(p.positions[p.indices[t + 1]] - a, p.positions[p.indices[t + 2]] - a));
    // Outward: the face normal points away from the cube's centre.
    EXPECT_GT(glm::dot(face, a), 0.0f);
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = p.normals[p.indices[t + size_t(k)]];
      EXPECT_NEAR(glm::dot(n, face), 1.0f, 1e-5f);
    }
  }
}

TEST(MeshNormals, SmoothSurfaceIsAreaWeighted) {
  // A shallow tent: two triangles meeting at 10 degrees share an edge, and
  // the big one dominates the shared vertices' normal.
  Primitive p;
  const float h = std::tan(glm::radians(10.0f));
  p.positions = {{0, 0, 0}, {0, 1, 0}, {-4, 0, 4 * h}, {1, 0, 0}};
  p.indices = {0, 1, 2, 0, 3, 1};
  GenerateNormals(&p);
  EXPECT_EQ(p.positions.size(), 4u);  // within the crease angle: no split
  const glm::vec3 big =
      glm::normalize(glm::cross(p.positions[1] - p.positions[0], p.positions[2] - p.positions[0]));
  const glm::vec3 small(0, 0, 1);
  const glm::vec3 shared = p.normals[0];
  EXPECT_NEAR(glm::length(shared), 1.0f, 1e-5f);
  EXPECT_GT(glm::dot(shared, big), glm::dot(shared, small));
  EXPECT_GT(shared.z, 0.0f);
}

TEST(MeshNormals, DegenerateTrianglesStillGetUnitNormals) {
  Primitive p;
  p.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}};  // collinear + unused vertex
  p.indices = {0, 1, 2};
  GenerateNormals(&p);
  for (const glm::vec3& n : p.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

TEST(MeshNormals, SplitVerticesKeepTheirUvs) {
  Primitive p = SharedCornerCube();
  for (const glm::vec3& x : p.positions) p.uvs.push_back({x.x, x.y});
  GenerateNormals(&p);
  ASSERT_EQ(p.uvs.size(), p.positions.size());
  for (size_t i = 0; i < p.positions.size(); ++i) {
    EXPECT_EQ(p.uvs[i], glm::vec2(p.positions[i].x, p.positions[i].y));
  }
}

}  // namespace scene_test
}  // namespace gistream
