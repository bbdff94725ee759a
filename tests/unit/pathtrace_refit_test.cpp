// The path tracer's BVH refit on a deformation (issue 18): a refit BVH over
// the posed triangles answers rays exactly as a BVH built from scratch on
// the same pose (same triangle, t within 1e-6 relative: Embree intersects
// the same stored triangles, only the tree around them differs), and the
// refit is declined (left for a rebuild) when the non-degenerate triangles
// change or the shadow tree's cost grows beyond its limit.
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "scene/state/scene_state.h"
#include "solvers/pathtrace/refit_quality.h"
#include "solvers/pathtrace/scene_bvh.h"
#include "support/deforming_scene.h"
#include "support/measurement.h"

namespace gistream {
namespace pathtrace_refit_test {

using pathtrace::RefitResult;
using pathtrace::SceneBvh;
using testing::DeformingTube;

// The skinned, morphed tube of support/deforming_scene.h with a rigid
// floor quad under it (its own Embree geometry).
std::shared_ptr<const Scene> TubeOnFloor() {
  Scene scene = testing::MakeDeformingTube(17, 24);
  Primitive floor;
  floor.positions = {{-2, -0.1f, -2}, {2, -0.1f, -2}, {2, -0.1f, 2}, {-2, -0.1f, 2}};
  floor.normals.assign(4, glm::vec3(0, 1, 0));
  floor.indices = {0, 2, 1, 0, 3, 2};
  floor.material = 0;
  for (const glm::vec3& v : floor.positions) floor.bounds.Extend(v);
  Mesh mesh;
  mesh.name = "floor";
  mesh.primitives.push_back(floor);
  scene.meshes.push_back(mesh);
  Node node;
  node.name = "floor";
  node.mesh = 1;
  scene.nodes.push_back(node);
  scene.roots.push_back(int(scene.nodes.size()) - 1);
  scene.bounds.Extend(mesh.primitives[0].bounds);
  return std::make_shared<const Scene>(std::move(scene));
}

// `count` small triangles in a row along +X (1 apart), one node with a
// morph-target mesh: target 0 carries triangle i to where triangle
// perm(i) sits (a shuffle: every group of neighbours is spread over the
// row at weight 1), target 1 moves triangle 0's third vertex onto its
// first (degenerate at weight 1).
std::shared_ptr<const Scene> ShuffledRow(int count) {
  Primitive p;
  Primitive::MorphTarget shuffle, collapse;
  std::vector<int> perm(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) perm[size_t(i)] = (i * 37 + 11) % count;  // count prime to 37
  for (int i = 0; i < count; ++i) {
    const glm::vec3 o(float(i), 0.0f, 0.0f);
    const glm::vec3 corners[3] = {o, o + glm::vec3(0.5f, 0, 0), o + glm::vec3(0, 0.5f, 0)};
    for (int k = 0; k < 3; ++k) {
      p.positions.push_back(corners[k]);
      p.normals.emplace_back(0, 0, 1);
      p.indices.push_back(uint32_t(3 * i + k));
      shuffle.positions.emplace_back(float(perm[size_t(i)] - i), 0.0f, 0.0f);
      collapse.positions.push_back(i == 0 && k == 2 ? corners[0] - corners[2] : glm::vec3(0.0f));
    }
  }
  for (const glm::vec3& v : p.positions) p.bounds.Extend(v);
  p.targets = {shuffle, collapse};
  p.material = 0;
  Scene scene;
  scene.name = "shuffled_row";
  Mesh mesh;
  mesh.name = "row";
  mesh.primitives.push_back(p);
  mesh.weights = {0.0f, 0.0f};
  scene.meshes.push_back(mesh);
  scene.materials.push_back(Material{});
  Node node;
  node.name = "row";
  node.mesh = 0;
  scene.nodes.push_back(node);
  scene.roots = {0};
  scene.bounds = p.bounds;
  scene.triangle_count = size_t(count);
  scene.vertex_count = p.positions.size();
  return std::make_shared<const Scene>(std::move(scene));
}

MorphWeightsUpdate Weights(uint32_t node, std::vector<float> weights) {
  MorphWeightsUpdate u;
  u.node = node;
  u.weights = std::move(weights);
  return u;
}

struct Ray {
  glm::vec3 origin, dir;
};

// Half the rays aimed at random points of random triangles of `bvh` (so
// that most hit), half in random directions; origins in the scene's box
// grown by its diagonal.
std::vector<Ray> RandomRays(const SceneBvh& bvh, int count) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Bounds box;
  for (const pathtrace::Triangle& t : bvh.triangles()) {
    box.Extend(t.p0);
    box.Extend(t.p0 + t.e1);
    box.Extend(t.p0 + t.e2);
  }
  const glm::vec3 lo = box.min - glm::vec3(bvh.scene_scale());
  const glm::vec3 size = box.extent() + glm::vec3(2.0f * bvh.scene_scale());
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    Ray r;
    r.origin = lo + size * glm::vec3(u(rng), u(rng), u(rng));
    if (i % 2 == 0) {
      const auto& t = bvh.triangles()[size_t(u(rng) * float(bvh.triangles().size() - 1))];
      float a = u(rng), b = u(rng);
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
      r.dir = t.p0 + a * t.e1 + b * t.e2 - r.origin;
    } else {
      r.dir = glm::vec3(u(rng), u(rng), u(rng)) * 2.0f - 1.0f;
    }
    r.dir = glm::normalize(r.dir);
    rays.push_back(r);
  }
  return rays;
}

// Every ray's hit in `got` is the one in `expected`: same triangle, t
// within 1e-6 relative. Returns the number of hits.
int ExpectSameHits(const SceneBvh& got, const SceneBvh& expected, const std::vector<Ray>& rays) {
  int hits = 0, mismatches = 0;
  for (const Ray& r : rays) {
    const pathtrace::Hit a = got.Intersect(r.origin, r.dir, 1e30f);
    const pathtrace::Hit b = expected.Intersect(r.origin, r.dir, 1e30f);
    const bool same = a.hit == b.hit &&
                      (!a.hit || (a.triangle == b.triangle && std::abs(a.t - b.t) <= 1e-6f * b.t));
    if (!same && ++mismatches <= 5) {
      ADD_FAILURE() << "ray from (" << r.origin.x << ", " << r.origin.y << ", " << r.origin.z
                    << "): hit " << a.hit << " triangle " << a.triangle << " t " << a.t
                    << " vs hit " << b.hit << " triangle " << b.triangle << " t " << b.t;
    }
    hits += b.hit ? 1 : 0;
    EXPECT_EQ(got.Occluded(r.origin, r.dir, 1e30f), b.hit);
  }
  EXPECT_EQ(mismatches, 0) << "of " << rays.size() << " rays";
  return hits;
}

TEST(PathtraceRefit, RefitAnswersRaysAsARebuildOfThePose) {
  SceneState state(TubeOnFloor());
  auto refit = SceneBvh::Build(state);
  ASSERT_TRUE(refit.ok()) << refit.status();
  auto rest = SceneBvh::Build(state);
  ASSERT_TRUE(rest.ok());
  // Bent 0.9 rad at the top (1.5 s of the 2 s animation) and bulged.
  AnimationUpdate seek;
  seek.animation = 0;
  seek.time = 1.5f;
  EXPECT_EQ(state.Apply(seek), kChangeDeformation);
  EXPECT_EQ(state.Apply(Weights(DeformingTube::kTubeNode, {0.8f})), kChangeDeformation);

  ASSERT_EQ((*refit)->Refit(state), RefitResult::kRefit);
  testing::RecordMeasurement("tube_refit_growth", (*refit)->refit_growth());
  auto rebuilt = SceneBvh::Build(state);
  ASSERT_TRUE(rebuilt.ok());

  // The same triangles, bit for bit, and the same light distribution.
  ASSERT_EQ((*refit)->triangles().size(), (*rebuilt)->triangles().size());
  for (size_t i = 0; i < (*rebuilt)->triangles().size(); ++i) {
    const pathtrace::Triangle& a = (*refit)->triangles()[i];
    const pathtrace::Triangle& b = (*rebuilt)->triangles()[i];
    ASSERT_TRUE(a.p0 == b.p0 && a.e1 == b.e1 && a.e2 == b.e2 && a.normal == b.normal &&
                a.n0 == b.n0 && a.area == b.area)
        << "triangle " << i;
  }
  EXPECT_EQ((*refit)->scene_scale(), (*rebuilt)->scene_scale());
  EXPECT_EQ((*refit)->emitter_cdf(), (*rebuilt)->emitter_cdf());

  const std::vector<Ray> rays = RandomRays(**rebuilt, 20000);
  const int hits = ExpectSameHits(**refit, **rebuilt, rays);
  EXPECT_GE(hits, 10000) << "half the rays aim at triangles";
  // And the pose is not the rest pose: many of these rays hit elsewhere there.
  int moved = 0;
  for (const Ray& r : rays) {
    const pathtrace::Hit a = (*rest)->Intersect(r.origin, r.dir, 1e30f);
    const pathtrace::Hit b = (*rebuilt)->Intersect(r.origin, r.dir, 1e30f);
    moved += a.hit != b.hit || a.triangle != b.triangle ? 1 : 0;
  }
  EXPECT_GE(moved, 2000);

  // Refits chain: back to the rest pose, as the rest BVH.
  seek.time = 0.0f;
  state.Apply(seek);
  state.Apply(Weights(DeformingTube::kTubeNode, {0.0f}));
  ASSERT_EQ((*refit)->Refit(state), RefitResult::kRefit);
  ExpectSameHits(**refit, **rest, rays);
}

TEST(PathtraceRefit, NothingToRefitWithoutADeformingMesh) {
  auto scene = std::make_shared<Scene>(*TubeOnFloor());
  scene->nodes[DeformingTube::kTubeNode].mesh = 1;  // two floors, nothing deforms
  SceneState state(scene);
  auto bvh = SceneBvh::Build(state);
  ASSERT_TRUE(bvh.ok());
  EXPECT_EQ((*bvh)->Refit(state), RefitResult::kNothingDeforms);
}

TEST(PathtraceRefit, CollapsedTriangleDeclinesTheRefit) {
  SceneState state(ShuffledRow(64));
  auto bvh = SceneBvh::Build(state);
  ASSERT_TRUE(bvh.ok());
  auto rest = SceneBvh::Build(state);
  ASSERT_TRUE(rest.ok());
  state.Apply(Weights(0, {0.0f, 1.0f}));  // triangle 0 degenerate: 63 triangles
  EXPECT_EQ((*bvh)->Refit(state), RefitResult::kTopology);
  // Declined: the BVH is still the built one.
  ExpectSameHits(**bvh, **rest, RandomRays(**rest, 2000));
  auto rebuilt = SceneBvh::Build(state);
  ASSERT_TRUE(rebuilt.ok());
  EXPECT_EQ((*rebuilt)->triangles().size(), 63u);
}

TEST(PathtraceRefit, ScatteredTrianglesDeclineTheRefitForQuality) {
  SceneState state(ShuffledRow(256));
  auto bvh = SceneBvh::Build(state);
  ASSERT_TRUE(bvh.ok());
  // A little of the shuffle (each triangle moves at most 0.01 x 255 along
  // the row): the tree's boxes grow by that much at most; refit.
  state.Apply(Weights(0, {0.01f, 0.0f}));
  EXPECT_EQ((*bvh)->Refit(state), RefitResult::kRefit);
  const double small = (*bvh)->refit_growth();
  testing::RecordMeasurement("small_shuffle_growth", small);
  EXPECT_LT(small, pathtrace::RefitQuality::kMaxCostGrowth);
  // All of it: every leaf's four neighbours end up spread along the row,
  // each box about as long as the root: declined.
  state.Apply(Weights(0, {1.0f, 0.0f}));
  EXPECT_EQ((*bvh)->Refit(state), RefitResult::kQuality);
  const double full = (*bvh)->refit_growth();
  testing::RecordMeasurement("full_shuffle_growth", full);
  EXPECT_GT(full, pathtrace::RefitQuality::kMaxCostGrowth);
  // A fresh build of the shuffled row is as good as the first.
  auto rebuilt = SceneBvh::Build(state);
  ASSERT_TRUE(rebuilt.ok());
  EXPECT_EQ((*rebuilt)->Refit(state), RefitResult::kRefit);  // the same pose
  EXPECT_NEAR((*rebuilt)->refit_growth(), 1.0, 1e-9);
}

}  // namespace pathtrace_refit_test
}  // namespace gistream
