// The GPU deformation pass (scene/gpu/gpu_deform.h, shaders/scene/deform.comp.glsl)
// against the one CPU implementation (scene/state/deform.h's DeformPrimitive, which
// SceneState::NodeMesh holds): the same vertices, skinned and morphed, read
// back from GpuScene's vertex buffer.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "scene/state/deform.h"
#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"
#include "support/deforming_scene.h"
#include "support/gl_context.h"
#include "support/measurement.h"

namespace gistream {
namespace gpu_deform_test {

using testing::DeformingTube;

// Float rounding of a different summation order (GPU fma, CPU glm) on
// coordinates of order 1: far below a 1e-4 relative error.
constexpr float kTolerance = 1e-4f;

class GpuDeformTest : public testing::GlContextTest {
 protected:
  // Reads back the posed vertices of `node`'s first draw and compares them
  // with DeformPrimitive on the state's pose.
  void ExpectMatchesCpu(const SceneState& state, const GpuScene& gpu, int node) {
    const DrawItem* draw = nullptr;
    for (const DrawItem& d : gpu.draws()) {
      if (d.node == node) draw = &d;
    }
    ASSERT_NE(draw, nullptr);
    ASSERT_NE(draw->base_vertex, draw->rest_vertex);  // its own posed copy
    std::vector<float> gpu_vertices(size_t(draw->vertex_count) * 8);
    glGetNamedBufferSubData(gpu.vertex_buffer(), GLintptr(draw->base_vertex) * 32,
                            GLsizeiptr(gpu_vertices.size() * sizeof(float)), gpu_vertices.data());
    const Scene& scene = state.scene();
    const Node& n = state.nodes()[size_t(node)];
    std::vector<glm::vec3> positions, normals;
    DeformPrimitive(
        scene.meshes[size_t(n.mesh)].primitives[size_t(draw->primitive)], MorphWeights(scene, n),
        JointMatrices(scene.skins[size_t(n.skin)], state.world(), node), &positions, &normals);
    ASSERT_EQ(positions.size(), size_t(draw->vertex_count));
    // NodeMesh (what the CPU stages read) is the same function's output.
    const Primitive& posed = state.NodeMesh(size_t(node)).primitives[size_t(draw->primitive)];
    float worst = 0.0f;
    for (size_t v = 0; v < positions.size(); ++v) {
      const float* g = &gpu_vertices[v * 8];
      const glm::vec3 p(g[0], g[1], g[2]), nrm(g[3], g[4], g[5]);
      worst = std::max(worst, glm::length(p - positions[v]));
      EXPECT_LE(glm::length(p - positions[v]), kTolerance * (1.0f + glm::length(positions[v])))
          << "vertex " << v;
      EXPECT_LE(glm::length(nrm - normals[v]), kTolerance) << "vertex " << v;
      EXPECT_EQ(posed.positions[v], positions[v]);
    }
    testing::RecordMeasurement("worst_position_error", worst);
  }
};

TEST_F(GpuDeformTest, SkinnedAndMorphedVerticesMatchTheCpuReference) {
  SceneState state(std::make_shared<const Scene>(testing::MakeDeformingTube()));
  NodeTransformUpdate bend;
  bend.node = DeformingTube::kBendJoint;
  bend.translation = glm::vec3(0.0f, 1.0f, 0.0f);
  bend.rotation = glm::angleAxis(0.9f, glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f)));
  bend.scale = glm::vec3(1.0f, 1.3f, 1.0f);
  EXPECT_EQ(state.Apply(bend), kChangeDeformation);  // a joint: the tube reshapes
  EXPECT_EQ(state.Apply(MorphWeightsUpdate{DeformingTube::kTubeNode, {0.7f}}), kChangeDeformation);
  auto gpu = GpuScene::Upload(state);
  ASSERT_TRUE(gpu.ok()) << gpu.status();
  ExpectMatchesCpu(state, **gpu, DeformingTube::kTubeNode);
}

TEST_F(GpuDeformTest, FollowsTheAnimationClockAfterUpload) {
  SceneState state(std::make_shared<const Scene>(testing::MakeDeformingTube()));
  auto gpu = GpuScene::Upload(state);
  ASSERT_TRUE(gpu.ok()) << gpu.status();
  EXPECT_FALSE((*gpu)->DeformPending(state));
  AnimationUpdate play;
  play.name = "bend";
  play.playing = true;
  play.time = 0.5f;
  EXPECT_EQ(state.Apply(play), kChangeDeformation);
  EXPECT_EQ(state.Advance(0.75), kChangeDeformation);  // at 1.25 s of 2
  EXPECT_NEAR(state.animations()[0].time, 1.25, 1e-9);
  ASSERT_TRUE((*gpu)->DeformPending(state));
  (*gpu)->Deform(state);
  EXPECT_FALSE((*gpu)->DeformPending(state));
  ExpectMatchesCpu(state, **gpu, DeformingTube::kTubeNode);
  // The upper half bent 0.75 rad about +Z, toward -X (its top by
  // sin(0.75) = 0.68 of the 1 m above the bend): the posed box follows.
  const Bounds& rest = state.scene().meshes[0].primitives[0].bounds;
  const Bounds& posed = state.NodeMesh(DeformingTube::kTubeNode).primitives[0].bounds;
  EXPECT_LT(posed.min.x, rest.min.x - 0.5f);
}

}  // namespace gpu_deform_test
}  // namespace gistream
