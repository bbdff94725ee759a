// The magnitude limits' building blocks (scene/magnitude_limits.h), the
// state-dependent update check (SceneState::CheckApply) and antiradiance's
// leaf count before splitting: no GL.
#include "scene/magnitude_limits.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "gltf_test_util.h"
#include "scene/state/scene_state.h"
#include "solvers/antiradiance/patches.h"

namespace gistream {
namespace magnitude_limits_test {

TEST(MagnitudeLimits, QuaternionsNearUnitAreRenormalisedOthersRejected) {
  auto q = CheckUnitQuaternion("q", glm::quat(1.005f, 0, 0, 0));
  ASSERT_TRUE(q.ok()) << q.status();
  EXPECT_FLOAT_EQ(glm::length(glm::vec4(q->w, q->x, q->y, q->z)), 1.0f);
  EXPECT_ERROR(CheckUnitQuaternion("q", glm::quat(0, 0, 0, 0)), kInvalidArgument,
               "q: zero-length quaternion");
  EXPECT_ERROR(CheckUnitQuaternion("q", glm::quat(0.5f, 0, 0, 0)), kInvalidArgument,
               "q: length 0.5 is not 1");
  EXPECT_ERROR(CheckUnitQuaternion("q", glm::quat(1, 0, std::nanf(""), 0)), kInvalidArgument,
               "q.y: nan is not finite");
}

TEST(MagnitudeLimits, PositionsAndScales) {
  EXPECT_TRUE(CheckPosition("p", glm::vec3(-1e6f, 0, 1e6f)).ok());
  EXPECT_ERROR(CheckPosition("p", glm::vec3(0, 1.5e6f, 0)), kInvalidArgument,
               "p.y: 1.5e+06 is beyond the world extent limit");
  EXPECT_TRUE(CheckScale("s", glm::vec3(-1e-6f, 1e6f, 1)).ok());  // mirrored is fine
  EXPECT_ERROR(CheckScale("s", glm::vec3(1, 1, 1e-7f)), kInvalidArgument, "s.z: 1e-07");
}

// root (scale 100) -> middle (scale 100) -> leaf mesh at x = 200: each
// value within its limit, the leaf at 2e6 m in the world.
Scene Chain() {
  Scene s;
  s.nodes.resize(3);
  s.nodes[0].scale = glm::vec3(100.0f);
  s.nodes[0].children = {1};
  s.nodes[1].parent = 0;
  s.nodes[1].scale = glm::vec3(100.0f);
  s.nodes[1].children = {2};
  s.nodes[2].parent = 1;
  s.nodes[2].mesh = 0;
  s.nodes[2].translation = glm::vec3(200.0f, 0, 0);
  s.roots = {0};
  Primitive p;
  p.positions = {glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)};
  p.normals.assign(3, glm::vec3(0, 0, 1));
  p.indices = {0, 1, 2};
  for (const glm::vec3& v : p.positions) p.bounds.Extend(v);
  s.meshes.push_back(Mesh{"tri", {p}});
  return s;
}

TEST(MagnitudeLimits, WorldExtentThroughTheHierarchy) {
  Scene s = Chain();
  EXPECT_ERROR(CheckWorldExtent(s, s.nodes, WorldMatrices(s, s.nodes), ""), kInvalidArgument,
               "nodes[2]: world position.x: 2e+06 is beyond the world extent limit");
  // The node's origin at 995000 m is inside, its mesh (1 x 1e4 m) is not.
  s.nodes[2].translation = glm::vec3(99.5f, 0, 0);
  EXPECT_ERROR(CheckWorldExtent(s, s.nodes, WorldMatrices(s, s.nodes), ""), kInvalidArgument,
               "nodes[2]: mesh vertex in world space.x: 1.005e+06");
  s.nodes[2].translation = glm::vec3(50.0f, 0, 0);
  EXPECT_TRUE(CheckWorldExtent(s, s.nodes, WorldMatrices(s, s.nodes), "").ok());
  s.nodes[1].scale = glm::vec3(1e-5f);  // world scale 1e-3: fine
  EXPECT_TRUE(CheckWorldExtent(s, s.nodes, WorldMatrices(s, s.nodes), "").ok());
  s.nodes[0].scale = glm::vec3(1e-5f);  // world scale 1e-10
  EXPECT_ERROR(CheckWorldExtent(s, s.nodes, WorldMatrices(s, s.nodes), ""), kInvalidArgument,
               "nodes[1]: world scale x 1e-10 is out of range");
}

TEST(MagnitudeLimits, CheckApplyLooksAtTheCurrentState) {
  Scene s = Chain();
  s.nodes[2].translation = glm::vec3(50.0f, 0, 0);
  s.materials.resize(1);
  s.materials[0].emissive_factor = glm::vec3(1e4f);
  SceneState state(std::make_shared<const Scene>(s));
  NodeTransformUpdate grow;
  grow.node = 0;
  grow.scale = glm::vec3(1000.0f);  // within the per-value limit, 5e6 m for the leaf
  EXPECT_ERROR(state.CheckApply(grow), kInvalidArgument,
               "update.node_transform: after it, nodes[2]: world position.x: 5e+06");
  MaterialUpdate strength;
  strength.emissive_strength = 1e7f;  // 1e4 x 1e7 = 1e11 nits
  EXPECT_ERROR(state.CheckApply(strength), kInvalidArgument,
               "update.material: after it, materials[0]: emissive factor x strength 1e+11");
  strength.emissive_strength = 1e6f;
  EXPECT_TRUE(state.CheckApply(strength).ok());
  // The check leaves the state alone.
  EXPECT_EQ(state.version(), 1u);
  EXPECT_EQ(state.nodes()[0].scale, glm::vec3(100.0f));
}

TEST(MagnitudeLimits, AntiradianceLeafCountMatchesTheSplit) {
  antiradiance::SourceTriangle t;
  t.p = {glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)};  // longest edge sqrt(2)
  t.normal = glm::vec3(0, 0, 1);
  t.albedo = glm::vec3(0.5f);
  const std::vector<std::vector<antiradiance::SourceTriangle>> groups = {{t, t}};
  for (const float max_edge : {2.0f, 1.0f, 0.3f, 0.05f}) {
    const antiradiance::Patches patches = antiradiance::BuildPatches(groups, max_edge);
    EXPECT_EQ(antiradiance::CountLeaves(groups, max_edge), patches.Leaves().size())
        << "max_edge " << max_edge;
  }
  // A tiny edge is capped at 12 splits: 4^12 leaves per triangle, counted
  // without making them.
  EXPECT_EQ(antiradiance::CountLeaves(groups, 1e-6f), 2u * (uint64_t(1) << 24));
}

}  // namespace magnitude_limits_test
}  // namespace gistream
