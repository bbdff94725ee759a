// The memory budget counts SceneState's posed copies (issue 18): each node
// that draws a deforming mesh holds a whole copy of it (scene_state.h),
// so CountSceneBytes adds that mesh's bytes once per such node, and
// nothing for a rigid instance.
#include <gtest/gtest.h>

#include <memory>

#include "scene/state/deform.h"
#include "scene/gpu/scene_memory.h"
#include "scene/state/scene_state.h"
#include "support/deforming_scene.h"

namespace gistream {
namespace posed_memory_test {

// What a copy of `mesh` holds (no proxies in these meshes).
uint64_t CopyBytes(const Mesh& mesh) {
  uint64_t bytes = 0;
  for (const Primitive& p : mesh.primitives) {
    bytes += p.positions.size() * 12 + p.normals.size() * 12 + p.uvs.size() * 8 +
             p.indices.size() * 4 + p.joints.size() * 8 + p.weights.size() * 16;
    for (const Primitive::MorphTarget& t : p.targets) {
      bytes += (t.positions.size() + t.normals.size()) * 12;
    }
  }
  return bytes;
}

TEST(PosedMemory, EachDeformingNodeCountsACopyOfItsMesh) {
  const Scene tube = testing::MakeDeformingTube();
  ASSERT_TRUE(NodeMeshDeforms(tube, testing::DeformingTube::kTubeNode));
  const uint64_t one = CountSceneBytes(tube).cpu;

  // A second skinned instance of the tube: one more node, one more copy
  // (and its primitives' G-buffer draws).
  Scene two = tube;
  two.nodes.push_back(two.nodes[testing::DeformingTube::kTubeNode]);
  two.roots.push_back(int(two.nodes.size()) - 1);
  ASSERT_TRUE(NodeMeshDeforms(two, two.nodes.size() - 1));
  EXPECT_EQ(CountSceneBytes(two).cpu - one,
            sizeof(Node) + CopyBytes(tube.meshes[0]) +
                kDrawListBytesPerDraw * tube.meshes[0].primitives.size());

  // A rigid mesh: its instance holds no copy (only its draws).
  Scene rigid = tube;
  Mesh plain = tube.meshes[0];
  plain.primitives[0].targets.clear();
  plain.primitives[0].joints.clear();
  plain.primitives[0].weights.clear();
  plain.weights.clear();
  rigid.meshes.push_back(plain);
  Node node;
  node.mesh = 1;
  rigid.nodes.push_back(node);
  rigid.roots.push_back(int(rigid.nodes.size()) - 1);
  ASSERT_FALSE(NodeMeshDeforms(rigid, rigid.nodes.size() - 1));
  EXPECT_EQ(CountSceneBytes(rigid).cpu - one,
            sizeof(Node) + CopyBytes(plain) + kDrawListBytesPerDraw * plain.primitives.size());

  // And the state does hold what was counted: a posed copy of the tube's
  // size for its node, none for the rigid one.
  SceneState state(std::make_shared<const Scene>(rigid));
  EXPECT_TRUE(state.Deforms(testing::DeformingTube::kTubeNode));
  EXPECT_FALSE(state.Deforms(rigid.nodes.size() - 1));
  EXPECT_EQ(CopyBytes(state.NodeMesh(testing::DeformingTube::kTubeNode)),
            CopyBytes(tube.meshes[0]));
  EXPECT_EQ(state.deforming_nodes().size(), 1u);
}

}  // namespace posed_memory_test
}  // namespace gistream
