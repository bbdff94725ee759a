// The antiradiance core (Dachsbacher et al. 2007) on hand-built scenes,
// without GL: the form factor of Eq. 17 against the analytic one, a
// blocker cancelled by antiradiance (Figs. 2 and 5), and the stability
// cases of issue 7 (stiff furnace, deep slab stack, surfaces almost
// touching).
#include <algorithm>
#include <cmath>
#include <functional>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "support/measurement.h"

#include "solvers/hierarchy/directional_bins.h"
#include "solvers/antiradiance/form_factor.h"
#include "solvers/antiradiance/links.h"
#include "solvers/antiradiance/patches.h"
#include "solvers/antiradiance/shared_elements.h"
#include "solvers/hierarchy/element_tree.h"
#include "solvers/hierarchy/surfels.h"
#include "solvers/antiradiance/transport.h"

namespace gistream::antiradiance {
namespace antiradiance_test {

constexpr float kPi = 3.14159265358979f;

// A w x h rectangle centred at c spanned by unit u, v; it faces u x v.
std::vector<SourceTriangle> Quad(glm::vec3 c, glm::vec3 u, glm::vec3 v, float w, float h,
                                 float rho) {
  const glm::vec3 a = c - 0.5f * w * u - 0.5f * h * v, b = a + w * u, d = a + h * v, e = b + h * v;
  const glm::vec3 n = glm::normalize(glm::cross(u, v));
  return {{{a, b, e}, n, glm::vec3(rho)}, {{a, e, d}, n, glm::vec3(rho)}};
}

const glm::vec3 kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1);

// Scene + its solution.
struct Solved {
  // `two_sided`: the tags of doubleSided materials (AddBackFaces).
  Solved(std::vector<std::vector<SourceTriangle>> groups, float max_edge, int m,
         const std::function<bool(int)>& two_sided = {}) {
    patches = BuildPatches(groups, max_edge);
    if (two_sided) mirrored = AddBackFaces(patches, two_sided);
    bins = *hierarchy::DirectionalBins::Create(m);
    transport = std::make_unique<Transport>(patches, bins, CreateLinks(patches, bins, nullptr));
  }
  // Leaves under root r.
  std::vector<int> LeavesOf(size_t r) const {
    const int end = r + 1 < patches.roots.size() ? patches.roots[r + 1] : patches.size();
    std::vector<int> out;
    for (int i = patches.roots[r]; i < end; ++i) {
      if (patches.is_leaf(i)) out.push_back(i);
    }
    return out;
  }
  // Area-weighted mean of indirect irradiance over root r's leaves (green).
  double MeanIrradiance(size_t r) const {
    double e = 0.0, a = 0.0;
    for (int i : LeavesOf(r)) {
      e += double(patches.area[size_t(i)]) * transport->indirect_irradiance()[size_t(i)].g;
      a += patches.area[size_t(i)];
    }
    return e / a;
  }
  std::vector<glm::vec3> Emission(size_t root, float l) const {
    std::vector<glm::vec3> e(size_t(patches.size()), glm::vec3(0.0f));
    for (int i : LeavesOf(root)) e[size_t(i)] = glm::vec3(l);
    return e;
  }
  Patches patches;
  int mirrored = 0;
  hierarchy::DirectionalBins bins;
  std::unique_ptr<Transport> transport;
};

TEST(AntiradianceBins, AntipodalUniformAndLookup) {
  const hierarchy::DirectionalBins b = *hierarchy::DirectionalBins::Create(128);
  EXPECT_NEAR(b.omega_bin() * 128, 4 * kPi, 1e-4);
  for (int j = 0; j < b.count(); ++j) {
    EXPECT_NEAR(glm::length(b.direction(j) + b.direction(b.opposite(j))), 0.0f, 1e-6f);
    EXPECT_EQ(b.Find(b.direction(j)), j);
  }
  // Spreading rows conserve energy.
  for (int l = 0; l < b.cone_levels(); ++l) {
    const auto [begin, end] = b.Row(l, 5);
    double s = 0.0;
    for (auto* t = begin; t != end; ++t) s += t->weight;
    EXPECT_NEAR(s, 1.0, 1e-5) << l;
  }
  EXPECT_FALSE(hierarchy::DirectionalBins::Create(7).ok());
  EXPECT_NE(hierarchy::DirectionalBins::Create(7).status().message().find("params.bins"),
            std::string::npos);
}

TEST(AntiradiancePatches, SharedHierarchyIsRelaidOutDepthFirst) {
  // A 6 x 6 grid of quads through the shared create_surfels /
  // create_hierarchy: same leaves and areas, parents before children.
  Primitive grid;
  const int n = 6;
  for (int y = 0; y <= n; ++y) {
    for (int x = 0; x <= n; ++x) {
      grid.positions.push_back({float(x) / n, 0.0f, float(y) / n});
      grid.normals.push_back({0, 1, 0});
    }
  }
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const uint32_t a = uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      grid.indices.insert(grid.indices.end(), {a, c, b, b, c, d});
    }
  }
  auto mesh = std::make_shared<hierarchy::ElementMesh>();
  mesh->surfels = hierarchy::CreateSurfels(grid);
  mesh->tree = hierarchy::CreateHierarchy(mesh->surfels);
  hierarchy::Elements elements({{mesh, 0, {}}});
  elements.Update({glm::mat4(1.0f)});
  const std::vector<glm::vec3> albedo(size_t(elements.leaf_count()), glm::vec3(0.5f));
  const std::vector<int> tag(size_t(elements.leaf_count()), 3);
  const Patches p = PatchesFromElements(elements, albedo, tag);
  EXPECT_EQ(p.size(), elements.node_count());
  EXPECT_EQ(int(p.Leaves().size()), elements.leaf_count());
  double leaf_area = 0.0, root_area = 0.0;
  for (int i = 0; i < p.size(); ++i) {
    if (p.is_leaf(i)) {
      leaf_area += p.area[size_t(i)];
      EXPECT_EQ(p.tag[size_t(i)], 3);
      EXPECT_EQ(p.albedo[size_t(i)].g, 0.5f);
      continue;
    }
    float children = 0.0f;
    for (int c : p.children[size_t(i)]) {
      if (c < 0) continue;
      EXPECT_GT(c, i);  // depth-first: push walks forward
      children += p.area[size_t(c)];
    }
    EXPECT_NEAR(children, p.area[size_t(i)], 1e-5f * p.area[size_t(i)]);
  }
  for (int r : p.roots) root_area += p.area[size_t(r)];
  EXPECT_NEAR(leaf_area, 1.0, 1e-5);
  EXPECT_NEAR(root_area, 1.0, 1e-5);
}

TEST(AntiradianceTransport, TwoPatchExchangeMatchesTheAnalyticFormFactor) {
  // Two parallel unit squares one unit apart: F = 0.19982 (Howell's
  // catalogue, C-11). A Lambertian sender of radiance 1 puts
  // pi * L * A * F of flux on the receiver; one global pass carries it.
  Solved s({Quad({0, 0, 0}, kX, kZ * -1.0f, 1, 1, 0), Quad({0, 1, 0}, kX, kZ, 1, 1, 0)}, 0.09f,
           512);
  // Both face each other: the first faces +y, the second -y.
  ASSERT_GT(s.patches.normal[size_t(s.patches.roots[0])].y, 0.9f);
  ASSERT_LT(s.patches.normal[size_t(s.patches.roots[1])].y, -0.9f);
  TransportSettings settings;
  settings.iterations = 1;
  const TransportResult r = s.transport->Solve({}, s.Emission(0, 1.0f), settings);
  EXPECT_FALSE(r.fallback);
  const double flux = s.MeanIrradiance(1) * 1.0;  // receiver area 1
  EXPECT_NEAR(flux / (kPi * 0.19982), 1.0, 0.02);
}

TEST(AntiradianceTransport, BlockerIsCancelledByAntiradiance) {
  // Sender (emitting, below) -> two-sided black blocker -> receiver above.
  // Iteration 1 lets the light through (no antiradiance yet); later
  // iterations cancel it (the paper's Fig. 2).
  auto scene = [](bool blocker) {
    std::vector<std::vector<SourceTriangle>> g = {Quad({0, 0, 0}, kX, -kZ, 0.3f, 0.3f, 0),
                                                  Quad({0, 1, 0}, kX, kZ, 0.3f, 0.3f, 0)};
    if (blocker) {
      g.push_back(Quad({0, 0.5f, 0}, kX, kZ, 1.2f, 1.2f, 0));    // faces the sender
      g.push_back(Quad({0, 0.52f, 0}, kX, -kZ, 1.2f, 1.2f, 0));  // faces the receiver
    }
    return g;
  };
  // Fewer bins blur the antiradiance more. Within a bin the cancelled
  // light is looked up along one direction (a parallel rather than a
  // perspective projection of the sender), which over-cancels: the
  // receiver ends slightly negative, less so with more bins (Fig. 13).
  double final_behind[2] = {0.0, 0.0};
  for (int m : {128, 512}) {
    TransportSettings settings;
    settings.iterations = 1;
    Solved open(scene(false), 0.1f, m);
    open.transport->Solve({}, open.Emission(0, 1.0f), settings);
    const double unblocked = open.MeanIrradiance(1);
    ASSERT_GT(unblocked, 0.0);
    Solved blocked(scene(true), 0.1f, m);
    std::vector<double> behind;
    TransportResult r;
    for (int it = 1; it <= 4; ++it) {
      settings.iterations = it;
      r = blocked.transport->Solve({}, blocked.Emission(0, 1.0f), settings);
      behind.push_back(blocked.MeanIrradiance(1) / unblocked);
    }
    EXPECT_FALSE(r.fallback);
    ASSERT_EQ(r.residual.size(), 4u);
    for (size_t k = 0; k < behind.size(); ++k) {
      testing::RecordMeasurement(absl::StrCat("behind_bins_", m, "_iteration_", k + 1), behind[k]);
      testing::RecordMeasurement(absl::StrCat("residual_bins_", m, "_iteration_", k + 1),
                                 r.residual[k]);
    }
    EXPECT_NEAR(behind[0], 1.0, 0.02) << m;  // no shadow after one iteration
    final_behind[m == 512] = behind[3];
    // Converged after two iterations (one layer of occlusion).
    EXPECT_LT(r.residual[3], 1e-6) << m;
  }
  EXPECT_LT(std::abs(final_behind[0]), 0.35);  // measured -0.27
  EXPECT_LT(std::abs(final_behind[1]), 0.15);  // measured -0.11
  EXPECT_LT(std::abs(final_behind[1]), std::abs(final_behind[0]));
}

TEST(AntiradiancePatches, BackFacesMirrorADoubleSidedRoot) {
  // Two roots; only the second (tag 7) is doubleSided.
  std::vector<std::vector<SourceTriangle>> groups = {Quad({0, 0, 0}, kX, kZ, 1, 1, 0.5f),
                                                     Quad({0, 1, 0}, kX, -kZ, 1, 1, 0.25f)};
  for (SourceTriangle& t : groups[1]) t.tag = 7;
  Patches p = BuildPatches(groups, 0.3f);
  const Patches before = p;
  EXPECT_EQ(AddBackFaces(p, [](int tag) { return tag == 7; }), 1);
  ASSERT_EQ(p.roots.size(), 3u);
  const int begin = before.roots[1], end = before.size(), copy = p.roots[2];
  EXPECT_EQ(copy, before.size());
  EXPECT_EQ(p.size(), before.size() + (end - begin));
  ASSERT_EQ(p.cell_begin.size(), size_t(p.size()) + 1);
  EXPECT_EQ(p.cell_begin.back(), p.cell.size());
  for (int i = begin; i < end; ++i) {
    const size_t a = size_t(i), b = size_t(copy + (i - begin));
    EXPECT_EQ(p.position[b], p.position[a]);
    EXPECT_EQ(p.normal[b], -p.normal[a]);
    EXPECT_EQ(p.area[b], p.area[a]);
    EXPECT_EQ(p.albedo[b], p.albedo[a]);
    EXPECT_EQ(p.tag[b], p.tag[a]);
    for (size_t k = 0; k < 4; ++k) {
      const int c = p.children[a][k];
      EXPECT_EQ(p.children[b][k], c < 0 ? -1 : c + (copy - begin));
    }
    ASSERT_EQ(p.Cell(int(b)).size(), p.Cell(i).size());
    for (size_t k = 0; k < p.Cell(i).size(); ++k) EXPECT_EQ(p.Cell(int(b))[k], p.Cell(i)[k]);
  }
  // The first root, and everything before the copy, unchanged.
  for (int i = 0; i < before.size(); ++i) EXPECT_EQ(p.normal[size_t(i)], before.normal[size_t(i)]);
}

TEST(AntiradianceTransport, DoubleSidedSheetBlocksAndReflectsOnItsBack) {
  // Sender (emitting, below, facing up) -> a one-sheet blocker facing up,
  // its back to the sender -> receiver above facing down. A solid object
  // is entered from its front, so the sheet alone passes the sender's
  // light through its back (the paper links only what a leaf's front
  // sees); doubleSided, its back face gathers that light, reflects it and
  // sends it back as antiradiance (AddBackFaces).
  auto scene = [] {
    std::vector<std::vector<SourceTriangle>> g = {Quad({0, 0, 0}, kX, -kZ, 0.3f, 0.3f, 0),
                                                  Quad({0, 1, 0}, kX, kZ, 0.3f, 0.3f, 0),
                                                  Quad({0, 0.5f, 0}, kX, -kZ, 1.2f, 1.2f, 0.5f)};
    for (SourceTriangle& t : g[2]) t.tag = 1;
    return g;
  };
  TransportSettings settings;
  settings.iterations = 8;
  Solved open(scene(), 0.1f, 128);
  open.transport->Solve({}, open.Emission(0, 1.0f), settings);
  Solved sheet(scene(), 0.1f, 128, [](int tag) { return tag == 1; });
  ASSERT_EQ(sheet.mirrored, 1);
  sheet.transport->Solve({}, sheet.Emission(0, 1.0f), settings);
  const double through = open.MeanIrradiance(1), behind = sheet.MeanIrradiance(1);
  testing::RecordMeasurement("one_sided_receiver", through);
  testing::RecordMeasurement("double_sided_receiver", behind);
  testing::RecordMeasurement("back_face", sheet.MeanIrradiance(3));
  ASSERT_GT(through, 0.0);
  // One-sided: no shadow (the sheet's front faces away from the sender).
  EXPECT_EQ(open.MeanIrradiance(2), 0.0);
  // Double-sided: a shadow as deep as the two-sheet blocker's at 128 bins
  // (BlockerIsCancelledByAntiradiance: |behind| < 0.35 of the light).
  EXPECT_LT(std::abs(behind), 0.35 * through);
  // Its back face gathers the sender's light: at least what the receiver
  // got through the open sheet, which is twice as far away.
  EXPECT_GT(sheet.MeanIrradiance(3), through);
}

// A closed box of six inward-facing walls, all emitting L_e = 1 with
// albedo rho: the exact solution is B = pi L_e / (1 - rho).
std::vector<std::vector<SourceTriangle>> Box(float rho) {
  return {Quad({0, -0.5f, 0}, kX, -kZ, 1, 1, rho), Quad({0, 0.5f, 0}, kX, kZ, 1, 1, rho),
          Quad({-0.5f, 0, 0}, kY, kZ, 1, 1, rho),  Quad({0.5f, 0, 0}, kY, -kZ, 1, 1, rho),
          Quad({0, 0, -0.5f}, kX, kY, 1, 1, rho),  Quad({0, 0, 0.5f}, kX, -kY, 1, 1, rho)};
}

TEST(AntiradianceFormFactor, PointToPolygonMatchesTheAnalyticValues) {
  const glm::vec3 x(0.0f), up(0, 1, 0);
  // A unit square one unit above, corner over the point (Howell's
  // catalogue, B-3): (1 / pi) (1 / sqrt 2) atan(1 / sqrt 2) = 0.138527.
  const CellQuad corner = {glm::vec3(0, 1, 0), glm::vec3(1, 1, 0), glm::vec3(1, 1, 1),
                           glm::vec3(0, 1, 1)};
  EXPECT_NEAR(PointToQuadsFormFactor({&corner, 1}, x, up), 0.138527, 1e-5);
  // As two triangles (a repeated corner): the same.
  const CellQuad halves[2] = {{corner[0], corner[1], corner[2], corner[2]},
                              {corner[0], corner[2], corner[3], corner[3]}};
  EXPECT_NEAR(PointToQuadsFormFactor(halves, x, up), 0.138527, 1e-5);
  // A huge square above covers the hemisphere: 1.
  const CellQuad sky = {glm::vec3(-1e4f, 1, -1e4f), glm::vec3(1e4f, 1, -1e4f),
                        glm::vec3(1e4f, 1, 1e4f), glm::vec3(-1e4f, 1, 1e4f)};
  EXPECT_NEAR(PointToQuadsFormFactor({&sky, 1}, x, up), 1.0, 1e-3);
  // A wall through the point's plane: only the part in front counts; a
  // half-infinite wall beside the point gives 1/2 (its horizon to zenith).
  const CellQuad wall = {glm::vec3(-1e4f, -1e4f, 1e-3f), glm::vec3(1e4f, -1e4f, 1e-3f),
                         glm::vec3(1e4f, 1e4f, 1e-3f), glm::vec3(-1e4f, 1e4f, 1e-3f)};
  EXPECT_NEAR(PointToQuadsFormFactor({&wall, 1}, x, up), 0.5, 1e-3);
  // Behind the point: nothing.
  const CellQuad below = {sky[0] - glm::vec3(0, 2, 0), sky[1] - glm::vec3(0, 2, 0),
                          sky[2] - glm::vec3(0, 2, 0), sky[3] - glm::vec3(0, 2, 0)};
  EXPECT_EQ(PointToQuadsFormFactor({&below, 1}, x, up), 0.0);
}

// The bundled furnace's mesh: a closed 2 m cube of six walls of n x n
// quads (separate vertices per wall), facing in, through the shared vertex
// hierarchy with each vertex's cell, as SurfelPatches builds it.
Patches VertexFurnace(int n, float rho) {
  Primitive p;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = -1; side <= 1; side += 2) {
      const uint32_t base = uint32_t(p.positions.size());
      glm::vec3 normal(0.0f);
      normal[axis] = -float(side);
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int y = 0; y <= n; ++y) {
        for (int x = 0; x <= n; ++x) {
          glm::vec3 q(0.0f);
          q[axis] = float(side);
          q[u] = -1.0f + 2.0f * float(x) / float(n);
          q[v] = -1.0f + 2.0f * float(y) / float(n);
          p.positions.push_back(q);
          p.normals.push_back(normal);
        }
      }
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          const uint32_t a = base + uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1),
                         d = c + 1;
          p.indices.insert(p.indices.end(), {a, b, c, b, d, c});
        }
      }
    }
  }
  auto mesh = std::make_shared<hierarchy::ElementMesh>();
  mesh->surfels = hierarchy::CreateSurfels(p);
  mesh->tree = hierarchy::CreateHierarchy(mesh->surfels);
  hierarchy::Elements elements({{mesh, 0, {}}});
  elements.Update({glm::mat4(1.0f)});
  const std::vector<glm::vec3> albedo(size_t(elements.leaf_count()), glm::vec3(rho));
  const std::vector<int> tag(size_t(elements.leaf_count()), 0);
  const std::vector<std::vector<CellQuad>> cells = VertexCells(p);
  return PatchesFromElements(elements, albedo, tag, &cells);
}

// Area-weighted mean of the leaves' indirect irradiance (green).
double MeanLeafIrradiance(const Patches& p, const Transport& t) {
  double e = 0.0, a = 0.0;
  for (int i : p.Leaves()) {
    e += double(p.area[size_t(i)]) * t.indirect_irradiance()[size_t(i)].g;
    a += p.area[size_t(i)];
  }
  return e / a;
}

TEST(AntiradianceEnergy, ClosedBoxGathersWhatItSends) {
  // One global pass in the furnace (every leaf's radiosity pi, L = 1):
  // every leaf should gather E = pi. Before the exact near-field form
  // factor and the bins' cosine correction (links.cpp) the mean was 2.9 %
  // low (edge leaves 12 to 20 % low), and every bounce lost that; the far
  // links' sigma-point kernel (links.cpp) took it from 0.99878 to 0.99926.
  const hierarchy::DirectionalBins bins = *hierarchy::DirectionalBins::Create(128);
  const Patches p = VertexFurnace(16, 0.0f);
  ASSERT_EQ(p.Cell(p.Leaves()[0]).empty(), false);
  LinkStats stats;
  Transport t(p, bins, CreateLinks(p, bins, &stats));
  EXPECT_GT(stats.exact, 0u);
  const std::vector<glm::vec3> emit(size_t(p.size()), glm::vec3(1.0f));
  TransportSettings settings;
  settings.iterations = 1;
  t.Solve({}, emit, settings);
  const double mean = MeanLeafIrradiance(p, t) / kPi;
  double lo = 1e30;
  for (int i : p.Leaves()) lo = std::min(lo, double(t.indirect_irradiance()[size_t(i)].g) / kPi);
  testing::RecordMeasurement("mean_e_over_pi", mean);
  testing::RecordMeasurement("lowest_leaf", lo);
  // Measured 0.99926: the rest is the bins' cosine integrals S(n) ~ pi
  // (99.94 % at 128 bins), which the far links do not scale away (links.cpp
  // says why: that made the iterated furnace +7 % at rho = 0.99). Never
  // above 1 (no energy created), 0.1 % below at most.
  EXPECT_LE(mean, 1.0 + 1e-4);
  EXPECT_GE(mean, 0.999);
  EXPECT_GE(lo, 0.85);  // measured 0.92 (was 0.77)
}

TEST(AntiradianceEnergy, StiffFurnaceConvergesNearTheExactValue) {
  // The same box emitting L_e = 1 through the direct term (E_d = pi) with
  // albedo rho, iterated to 1e-5: E = pi rho / (1 - rho). Measured
  // -0.09 % (0.5), -0.5 % (0.9), -4.7 % (0.99) of E (-0.2, -0.5, -4.4 %
  // before the far links' sigma points): on this coarse box the iterated
  // value follows the hierarchy's non-uniform per-leaf errors more than
  // the uniform gather (0.9993 per pass); the 16 x 16 box reads -0.14 % at
  // 0.99 (server/solvers/antiradiance/README.md, Energy).
  const hierarchy::DirectionalBins bins = *hierarchy::DirectionalBins::Create(128);
  for (float rho : {0.5f, 0.9f, 0.99f}) {
    const Patches p = VertexFurnace(8, rho);
    Transport t(p, bins, CreateLinks(p, bins, nullptr));
    const std::vector<glm::vec3> direct(size_t(p.size()), glm::vec3(kPi));
    TransportSettings settings;
    settings.iterations = 4096;
    settings.tolerance = 1e-5;
    const TransportResult r = t.Solve(direct, {}, settings);
    EXPECT_FALSE(r.cap_reached) << rho;
    const double exact = kPi * rho / (1.0 - rho);
    const double ratio = MeanLeafIrradiance(p, t) / exact;
    testing::RecordMeasurement(absl::StrCat("ratio_rho_", rho), ratio);
    testing::RecordMeasurement(absl::StrCat("iterations_rho_", rho), r.iterations);
    EXPECT_LE(ratio, 1.0 + 1e-4) << rho;
    EXPECT_GE(ratio, rho < 0.95f ? 0.99 : 0.94) << rho;
  }
}

TEST(AntiradianceStability, StiffFurnaceStaysFiniteAndBounded) {
  for (float rho : {0.9f, 0.99f}) {
    Solved s(Box(rho), 0.2f, 128);
    std::vector<glm::vec3> emit(size_t(s.patches.size()), glm::vec3(1.0f));
    TransportSettings settings;
    settings.iterations = 48;
    const TransportResult r = s.transport->Solve({}, emit, settings);
    EXPECT_FALSE(r.non_finite);
    // The emission is transported (source B = pi L_e): the indirect
    // irradiance after n iterations is pi L_e (1 + rho + ... + rho^(n-1)),
    // the fixed point pi L_e / (1 - rho). (This test used rho times these,
    // which only the former ~10 % loss let pass.)
    const double bound = kPi / (1.0 - rho);
    const double truncated = kPi * (1.0 - std::pow(rho, 48)) / (1.0 - rho);
    double lo = 1e30, hi = -1e30;
    for (int i : s.patches.Leaves()) {
      const glm::vec3 e = s.transport->indirect_irradiance()[size_t(i)];
      ASSERT_TRUE(std::isfinite(e.g));
      lo = std::min(lo, double(e.g)), hi = std::max(hi, double(e.g));
    }
    const double mean = MeanLeafIrradiance(s.patches, *s.transport);
    testing::RecordMeasurement(absl::StrCat("mean_over_truncated_rho_", rho), mean / truncated);
    // No energy made over the box; a leaf may pass the fixed point by the
    // hierarchy's per-leaf error (a cluster's light is pushed to its leaves
    // unchanged; measured +3.7 % at 0.9).
    EXPECT_LE(mean, bound) << rho;
    EXPECT_LE(hi, 1.1 * bound) << rho;
    EXPECT_GE(lo, 0.0) << rho;
    // The near leaves' exact form factors, the bins' cosine correction and
    // the far links' sigma-point kernel (links.cpp) carry what a closed box
    // sends: after 48 bounces within 2 % of the truncated series at 0.9 and
    // 5 % at 0.99 (measured -0.5 % and -1.3 %; it was -1.2 % and -2.8 %,
    // and before that about -11 % and -39 %).
    EXPECT_NEAR(mean / truncated, 1.0, rho < 0.95f ? 0.02 : 0.05)
        << rho << " scheme " << int(r.scheme_used);
  }
}

TEST(AntiradianceStability, DeepSlabStackNeedsManyAntiradianceSteps) {
  // Six closed slabs between an emitter and a receiver: every layer needs
  // one more antiradiance step to be cancelled. The symmetric scheme
  // diverges here (the discrete U creates energy between the close
  // plates) and must fall back; the asymmetric one converges.
  std::vector<std::vector<SourceTriangle>> g = {Quad({0, 0, 0}, kX, -kZ, 0.3f, 0.3f, 0.5f),
                                                Quad({0, 1.6f, 0}, kX, kZ, 0.3f, 0.3f, 0.5f)};
  for (int k = 0; k < 6; ++k) {
    const float y = 0.3f + 0.2f * float(k);
    g.push_back(Quad({0, y, 0}, kX, kZ, 0.7f, 0.7f, 0.5f));
    g.push_back(Quad({0, y + 0.05f, 0}, kX, -kZ, 0.7f, 0.7f, 0.5f));
  }
  Solved s(g, 0.15f, 128);
  for (Scheme scheme : {Scheme::kSymmetric, Scheme::kAsymmetric}) {
    TransportSettings settings;
    settings.iterations = 8;
    settings.scheme = scheme;
    const TransportResult r = s.transport->Solve({}, s.Emission(0, 1.0f), settings);
    EXPECT_FALSE(r.non_finite);
    double lo = 0.0, hi = 0.0;
    for (int i : s.patches.Leaves()) {
      const double e = s.transport->indirect_irradiance()[size_t(i)].g;
      ASSERT_TRUE(std::isfinite(e));
      lo = std::min(lo, e), hi = std::max(hi, e);
    }
    testing::RecordMeasurement(absl::StrCat("passes_scheme_", int(scheme)), r.global_passes);
    testing::RecordMeasurement(absl::StrCat("residual_scheme_", int(scheme)), r.residual.back());
    EXPECT_EQ(r.scheme_used, Scheme::kAsymmetric);
    EXPECT_EQ(r.fallback,
              scheme == Scheme::kSymmetric);  // the symmetric residual grew twice in a row
    if (r.fallback) {
      EXPECT_FALSE(r.symmetric_residual.empty());
    }
    // Total intensity dips below zero where antiradiance over-cancels
    // (see the blocker): stated tolerance 20 % of the brightest leaf.
    EXPECT_GE(lo, -0.2 * hi) << int(scheme);
    // The receiver behind eight slabs is dark.
    EXPECT_LT(std::abs(s.MeanIrradiance(1)), 0.1 * hi) << int(scheme);
  }
}

TEST(AntiradianceStability, SurfacesAlmostTouching) {
  // Two facing squares 0.1 mm apart (a paper on a table): the 1 / r^2 of
  // Eq. 17 is huge, but the oracle subdivides to leaves and spreads them
  // over a hemisphere; nothing may blow up or exceed the furnace bound.
  const float rho = 0.9f;
  Solved s({Quad({0, 0, 0}, kX, -kZ, 1, 1, rho), Quad({0, 1e-4f, 0}, kX, kZ, 1, 1, rho)}, 0.2f,
           128);
  std::vector<glm::vec3> emit(size_t(s.patches.size()), glm::vec3(1.0f));
  TransportSettings settings;
  settings.iterations = 8;
  const TransportResult r = s.transport->Solve({}, emit, settings);
  EXPECT_FALSE(r.non_finite);
  for (int i : s.patches.Leaves()) {
    const float e = s.transport->indirect_irradiance()[size_t(i)].g;
    ASSERT_TRUE(std::isfinite(e));
    EXPECT_GE(e, 0.0f);
    EXPECT_LE(e, 1.05f * kPi * rho / (1.0f - rho));
  }
}

}  // namespace antiradiance_test
}  // namespace gistream::antiradiance
