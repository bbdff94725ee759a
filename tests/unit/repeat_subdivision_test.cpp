// hierarchy::RepeatSubdivision (issue 18): a deforming mesh keeps the
// element layout of the pose it was subdivided at. Repeated on the same
// pose it is SubdivideLongEdges' own output, bit for bit; on another pose
// every added vertex is the midpoint of its (posed) parents, where
// subdividing that pose afresh would put it when the same edges are long.
#include <gtest/gtest.h>

#include "solvers/hierarchy/subdivide.h"

namespace gistream {
namespace repeat_subdivision_test {

// Two triangles of a 4 x 1 quad: its long edges split at max_edge 0.6.
Primitive Quad(float stretch) {
  Primitive p;
  p.positions = {{0, 0, 0}, {4 * stretch, 0, 0}, {4 * stretch, 1, 0}, {0, 1, 0}};
  p.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0.6f, 0.8f}, {0, 0, 1}};
  p.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  p.indices = {0, 1, 2, 0, 2, 3};
  for (const glm::vec3& v : p.positions) p.bounds.Extend(v);
  return p;
}

TEST(RepeatSubdivision, SamePoseIsTheSubdivision) {
  hierarchy::Midpoints midpoints;
  const Primitive rest = Quad(1.0f);
  const Primitive subdivided = hierarchy::SubdivideLongEdges(rest, 0.6f, &midpoints);
  ASSERT_GT(subdivided.positions.size(), rest.positions.size());
  EXPECT_EQ(midpoints.size(), subdivided.positions.size() - rest.positions.size());
  const Primitive again = hierarchy::RepeatSubdivision(rest, subdivided, midpoints);
  EXPECT_EQ(again.positions, subdivided.positions);
  EXPECT_EQ(again.normals, subdivided.normals);
  EXPECT_EQ(again.uvs, subdivided.uvs);
  EXPECT_EQ(again.indices, subdivided.indices);
}

TEST(RepeatSubdivision, AnotherPoseKeepsTheLayout) {
  hierarchy::Midpoints midpoints;
  const Primitive subdivided = hierarchy::SubdivideLongEdges(Quad(1.0f), 0.6f, &midpoints);
  // Stretched 1.5x along X: a fresh subdivision would split more often,
  // the repeated one keeps the rest pose's vertices and triangles.
  const Primitive posed = Quad(1.5f);
  const Primitive again = hierarchy::RepeatSubdivision(posed, subdivided, midpoints);
  ASSERT_EQ(again.positions.size(), subdivided.positions.size());
  EXPECT_EQ(again.indices, subdivided.indices);
  EXPECT_EQ(again.uvs, subdivided.uvs);
  for (size_t i = 0; i < again.positions.size(); ++i) {
    // The stretch is linear: every vertex is its rest position stretched
    // (tolerance: float midpoints of midpoints).
    const glm::vec3 expected = subdivided.positions[i] * glm::vec3(1.5f, 1.0f, 1.0f);
    EXPECT_NEAR(again.positions[i].x, expected.x, 1e-6f) << i;
    EXPECT_EQ(again.positions[i].y, expected.y) << i;
    EXPECT_NEAR(glm::length(again.normals[i]), 1.0f, 1e-6f) << i;
  }
  EXPECT_GT(hierarchy::SubdivideLongEdges(posed, 0.6f).positions.size(), again.positions.size());
}

}  // namespace repeat_subdivision_test
}  // namespace gistream
