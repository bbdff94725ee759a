// hierarchy::SubdividedVertexBound, which the vertex-based solvers' memory
// estimates use, is an upper bound on what SubdivideLongEdges makes.
#include <gtest/gtest.h>

#include "scene/gltf/gltf_import.h"
#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"
#include "solvers/hierarchy/subdivide.h"
#include "support/gl_context.h"

namespace gistream {
namespace subdivide_bound_test {

TEST(SubdividedVertexBound, BoundsTheVerticesTheSubdivisionMakes) {
  const auto context = testing::CurrentGlContext();
  ASSERT_TRUE(context);
  for (const char* name : {"cornell_box_coarse", "cornell_box"}) {
    SCOPED_TRACE(name);
    auto scene = ImportSceneByName(std::string(GISTREAM_SOURCE_DIR "/scenes"), name, {});
    ASSERT_TRUE(scene.ok()) << scene.status();
    SceneState state(std::make_shared<const Scene>(*std::move(scene)));
    auto gpu = GpuScene::Upload(state);
    ASSERT_TRUE(gpu.ok()) << gpu.status();
    uint64_t original = 0, subdivided = 0;
    for (const Node& node : state.nodes()) {
      if (node.mesh < 0) continue;
      const Mesh& mesh = state.scene().meshes[size_t(node.mesh)];
      for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const float max_edge = hierarchy::LocalMaxEdge(state, **gpu, node.mesh, int(p));
        original += mesh.primitives[p].positions.size();
        subdivided += hierarchy::SubdivideLongEdges(mesh.primitives[p], max_edge).positions.size();
      }
    }
    const uint64_t bound = hierarchy::SubdividedVertexBound(state, **gpu, false);
    EXPECT_GE(bound, subdivided);
    // Not a wild over-estimate: within 4x of the vertices really made.
    EXPECT_LE(bound, 4 * subdivided);
    if (std::string(name) == "cornell_box_coarse") {
      EXPECT_GT(subdivided, original);
    }
  }
  context->ReleaseCurrent();
}

}  // namespace subdivide_bound_test
}  // namespace gistream
