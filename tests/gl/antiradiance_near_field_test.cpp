// antiradiance's elements near a double-sided emitter (issue 29, item 3;
// solvers/antiradiance/near_field.h): a coarse ceiling over a lamp quad a
// centimetre below it is refined to the gap above the lamp, graded
// outward, left coarse far from it and not refined at all when the lamp
// is single-sided or dark; the memory estimate covers the added leaves.
#include <algorithm>
#include <span>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/gltf/gltf_import.h"
#include "scene/gpu/gpu_scene.h"
#include "solvers/antiradiance/near_field.h"
#include "solvers/antiradiance/shared_elements.h"
#include "solvers/hierarchy/subdivide.h"
#include "support/gl_context.h"
#include "support/gltf_builder.h"

namespace gistream {
namespace antiradiance_near_field_test {

constexpr float kGap = 0.01f;

struct Built {
  antiradiance::Patches patches;
  uint64_t bound = 0;       // the estimate's vertex bound
  uint64_t near_bound = 0;  // of it, the near field's
};

// A 1 m ceiling of 8 x 8 quads (material 0) facing down, a 30 cm lamp of
// 2 x 2 quads (material 1) kGap under its centre, and a floor 1 m below
// so the scene's size is a room's; `second_ceiling`: the ceiling's mesh
// drawn again 3 m aside, far from the lamp (one refined mesh serves both).
Built Build(bool double_sided, float emission, bool second_ceiling = false) {
  testing::GltfBuilder b;
  const int grey = b.AddMaterial("grey", {0.7f, 0.7f, 0.7f});
  const int lamp = b.AddMaterial("lamp", {0.78f, 0.78f, 0.78f}, {emission, emission, emission});
  if (double_sided) b.SetDoubleSided(lamp);
  b.AddQuad("ceiling", {0, 0.5f, 0}, {0.5f, 0, 0}, {0, 0, 0.5f}, grey, 8);
  b.AddQuad("floor", {0, -0.5f, 0}, {0, 0, 0.5f}, {0.5f, 0, 0}, grey, 8);
  b.AddQuad("lamp", {0, 0.5f - kGap, 0}, {0.15f, 0, 0}, {0, 0, 0.15f}, lamp, 2);
  std::string json = b.ToJson();
  if (second_ceiling) {
    nlohmann::json doc = nlohmann::json::parse(json);
    nlohmann::json node = doc["nodes"][0];  // the ceiling's
    node.erase("name");
    node["translation"] = {3.0, 0.0, 0.0};
    doc["nodes"].push_back(node);
    doc["scenes"][0]["nodes"].push_back(doc["nodes"].size() - 1);
    json = doc.dump();
  }
  auto scene = ImportGltf(
      std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()), {});
  EXPECT_TRUE(scene.ok()) << scene.status();
  if (!scene.ok()) return {};
  SceneState state(std::make_shared<const Scene>(*std::move(scene)));
  auto gpu = GpuScene::Upload(state);
  EXPECT_TRUE(gpu.ok()) << gpu.status();
  if (!gpu.ok()) return {};
  Built out;
  antiradiance::SurfelCache cache;
  out.patches = antiradiance::SurfelPatches(state, **gpu, cache);
  out.near_bound = antiradiance::NearFieldVertexBound(state, **gpu, false);
  out.bound = hierarchy::SubdividedVertexBound(state, **gpu, false, true) + out.near_bound;
  return out;
}

// The largest distance from a ceiling leaf's centre to a corner of its
// cell, over the ceiling leaves whose centre lies within `inside` of the
// lamp's centre line (or beyond `outside`, when given).
float LargestCell(const antiradiance::Patches& p, float inside, float outside = -1.0f) {
  float largest = 0.0f;
  for (int leaf : p.Leaves()) {
    const glm::vec3 c = p.position[size_t(leaf)];
    if (p.tag[size_t(leaf)] != 0 || c.y < 0.4f) continue;  // the ceiling only
    const float lateral = std::max(std::abs(c.x), std::abs(c.z));
    if (outside >= 0.0f ? lateral < outside : lateral > inside) continue;
    for (const antiradiance::CellQuad& q : p.Cell(leaf))
      for (const glm::vec3& v : q) largest = std::max(largest, glm::length(v - c));
  }
  return largest;
}

class AntiradianceNearField : public testing::GlContextTest {};

TEST_F(AntiradianceNearField, ACeilingOverADoubleSidedLampIsRefinedToItsDistance) {
  const Built lit = Build(true, 1.0f);
  // Above the lamp every edge is at most kNearFieldEdge x 1 cm (the
  // midpoints' distance to the lamp's box), so a cell, the vertex's third
  // of its triangles, reaches at most 2/3 of that from its vertex (the
  // triangles' centroids; 1.65 cm measured). The 12.5 cm quads' cells
  // reach 6.8 cm.
  const float above = LargestCell(lit.patches, 0.12f);
  EXPECT_GT(above, 0.0f);
  EXPECT_LE(above, antiradiance::kNearFieldEdge * kGap * 2.0f / 3.0f);
  // Far from it (45 cm from the centre line, 30 cm past the lamp's edge)
  // the ceiling keeps its coarse quads.
  EXPECT_GT(LargestCell(lit.patches, 0.0f, 0.45f), 0.06f);
  // Unrefined: a single-sided lamp lights nothing above it, a dark one
  // nothing at all; their ceilings keep the coarse cells.
  for (const auto& [double_sided, emission] : {std::pair(false, 1.0f), std::pair(true, 0.0f)}) {
    const Built plain = Build(double_sided, emission);
    EXPECT_GT(LargestCell(plain.patches, 0.12f), 0.06f) << double_sided << " " << emission;
    EXPECT_EQ(plain.near_bound, 0u);
    EXPECT_LT(plain.patches.Leaves().size(), lit.patches.Leaves().size());
  }
}

// The memory estimate's vertex bound (antiradiance_estimates.cpp) covers
// the refined leaves, the lamp's mirrored back faces included.
TEST_F(AntiradianceNearField, TheMemoryEstimateCoversTheRefinedLeaves) {
  const Built lit = Build(true, 1.0f);
  const uint64_t leaves = lit.patches.Leaves().size();
  EXPECT_GT(lit.near_bound, 0u);
  EXPECT_GE(lit.bound, leaves);
  EXPECT_LE(lit.bound, 8 * leaves);
  // An instance far from the lamp draws the same refined mesh, and is
  // counted with it (its own box alone would not count the refinement).
  const Built two = Build(true, 1.0f, /*second_ceiling=*/true);
  EXPECT_GE(two.bound, two.patches.Leaves().size());
  EXPECT_GE(two.near_bound, 2 * lit.near_bound);
}

}  // namespace antiradiance_near_field_test
}  // namespace gistream
