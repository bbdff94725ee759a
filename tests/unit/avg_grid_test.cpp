// CPU parts of the `avg` solver: the triangle/box test, the approximate
// visibility grid (watertight shell, ray marching), and VPL tracing
// (energy of the first bounce, determinism).
#include <cmath>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include "support/measurement.h"

#include "scene/gltf/gltf_import.h"
#include "solvers/brdf_albedo.h"
#include "solvers/avg/quasi_random.h"
#include "solvers/avg/tri_box_overlap.h"
#include "solvers/avg/voxel_grid.h"
#include "solvers/avg/vpl_lights.h"
#include "solvers/avg/vpl_tracer.h"

namespace gistream {
namespace avg_grid_test {

using avg::VoxelGrid;

std::unique_ptr<SceneState> LoadBundled(const std::string& name) {
  auto scene = ImportSceneByName(std::string(GISTREAM_SOURCE_DIR "/scenes"), name, {});
  EXPECT_TRUE(scene.ok()) << scene.status();
  if (!scene.ok()) return nullptr;
  return std::make_unique<SceneState>(std::make_shared<const Scene>(*std::move(scene)));
}

// A scene of quads (each two triangles) in one mesh, plus optional lights.
struct QuadSpec {
  glm::vec3 center, u, v;  // half-vectors; faces along cross(u, v)
  int material = 0;
};
std::shared_ptr<const Scene> QuadScene(const std::vector<QuadSpec>& quads,
                                       std::vector<Material> materials,
                                       std::vector<std::pair<Light, glm::vec3>> lights = {}) {
  auto scene = std::make_shared<Scene>();
  Mesh mesh;
  for (const QuadSpec& q : quads) {
    Primitive p;
    const glm::vec3 n = glm::normalize(glm::cross(q.u, q.v));
    p.positions = {q.center - q.u - q.v, q.center + q.u - q.v, q.center + q.u + q.v,
                   q.center - q.u + q.v};
    p.normals = {n, n, n, n};
    p.indices = {0, 1, 2, 0, 2, 3};
    p.material = q.material;
    for (const glm::vec3& x : p.positions) p.bounds.Extend(x);
    scene->bounds.Extend(p.bounds);
    mesh.primitives.push_back(p);
  }
  scene->meshes.push_back(mesh);
  scene->materials = std::move(materials);
  Node node;
  node.mesh = 0;
  scene->nodes.push_back(node);
  scene->roots.push_back(0);
  for (const auto& [light, position] : lights) {
    Node ln;
    ln.light = int(scene->lights.size());
    ln.translation = position;
    scene->lights.push_back(light);
    scene->roots.push_back(int(scene->nodes.size()));
    scene->nodes.push_back(ln);
  }
  return scene;
}

// A closed cube [-1, 1]^3, one material (face orientation does not matter:
// surfaces are two-sided for VPL tracing).
std::vector<QuadSpec> ClosedCube() {
  return {{{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
          {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
          {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}};
}

// Unit directions spread over the sphere (Fibonacci lattice).
std::vector<glm::vec3> SphereDirections(int n) {
  std::vector<glm::vec3> out;
  const float golden = glm::pi<float>() * (3.0f - std::sqrt(5.0f));
  for (int i = 0; i < n; ++i) {
    const float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
    const float r = std::sqrt(1.0f - z * z);
    out.emplace_back(r * std::cos(golden * float(i)), r * std::sin(golden * float(i)), z);
  }
  return out;
}

TEST(AvgTriangleBox, HandExamples) {
  const glm::vec3 c(0.0f), h(0.5f);
  // Lies in the box's mid-plane, larger than the box.
  EXPECT_TRUE(avg::TriangleBoxOverlap(c, h, {-5, -5, 0}, {5, -5, 0}, {0, 5, 0}));
  // Parallel to a face (z = 0.5 exactly touches, 0.51 misses).
  EXPECT_TRUE(avg::TriangleBoxOverlap(c, h, {-5, -5, 0.5f}, {5, -5, 0.5f}, {0, 5, 0.5f}));
  EXPECT_FALSE(avg::TriangleBoxOverlap(c, h, {-5, -5, 0.51f}, {5, -5, 0.51f}, {0, 5, 0.51f}));
  // Bounding boxes overlap, the plane misses the box: x + y + z = 2 (the
  // box corner reaches 1.5).
  EXPECT_FALSE(avg::TriangleBoxOverlap(c, h, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}));
  // x + y + z = 1.4 cuts the corner.
  EXPECT_TRUE(avg::TriangleBoxOverlap(c, h, {1.4f, 0, 0}, {0, 1.4f, 0}, {0, 0, 1.4f}));
  // Beside an edge: the bounding boxes overlap and the plane cuts the box,
  // but the triangle stops short of it; only an edge x box-axis separates.
  // (In the plane z = 0, the corner x + y >= 1.8 of the square 0.3..1.5.)
  EXPECT_FALSE(avg::TriangleBoxOverlap(c, h, {0.3f, 1.5f, 0}, {1.5f, 0.3f, 0}, {1.5f, 1.5f, 0}));
  EXPECT_TRUE(avg::TriangleBoxOverlap(c, h, {0.3f, 0.5f, 0}, {1.5f, 0.3f, 0}, {1.5f, 1.5f, 0}));
}

TEST(AvgGrid, FurnaceShellIsClosed) {
  // Rays from inside the closed furnace cube never escape the voxel shell
  // (the voxelization is watertight), at several grid sizes.
  auto state = LoadBundled("furnace");
  ASSERT_TRUE(state);
  const std::vector<glm::vec3> dirs = SphereDirections(2000);
  for (int n : {16, 32, 64, 128}) {
    const VoxelGrid grid = VoxelGrid::Build(*state, n);
    int escaped = 0;
    for (const glm::vec3 o : {glm::vec3(0.0f), glm::vec3(0.9f, 0.9f, 0.9f),
                              glm::vec3(-0.95f, 0.3f, 0.97f), glm::vec3(0.5f, -0.99f, -0.2f)}) {
      for (const glm::vec3& d : dirs) {
        if (!grid.March(o, d, glm::vec3(0.0f), false)) ++escaped;
      }
    }
    EXPECT_EQ(escaped, 0) << "grid " << n;
  }
}

TEST(AvgGrid, ThinSheetsNearlyParallelToAnAxisAreWatertight) {
  // A zero-thickness sheet tilted 0.5 degrees off the y-z plane (nearly
  // parallel to the x projection axis that a rasterizer would miss) and one
  // lying exactly on a voxel boundary: no ray crosses either.
  const float tilt = glm::radians(0.5f);
  const glm::vec3 u(std::sin(tilt), std::cos(tilt), 0.0f);
  const auto scene = QuadScene(
      {{{0.0f, 0.0f, 0.0f}, u * 2.0f, {0, 0, 2}}, {{0.5f, 0.0f, 0.0f}, {0, 2, 0}, {0, 0, 2}}},
      {Material{}});
  const SceneState state(scene);
  const VoxelGrid grid = VoxelGrid::Build(state, 32);
  int crossed = 0;
  int tested = 0;
  for (const glm::vec3& d : SphereDirections(4000)) {
    // Rays from the left (x = -0.5) that cross x = 0 within the sheets'
    // extent (|y|, |z| < 2): d.x > 0.5 keeps the lateral drift under 0.9.
    if (d.x < 0.5f) continue;
    ++tested;
    const glm::vec3 o(-0.5f, 0.4f * d.y, 0.4f * d.z);
    const auto hit = grid.March(o, d, glm::vec3(0.0f), false);
    if (!hit) {
      ++crossed;
      continue;
    }
    // The first hit is the tilted sheet's voxel: x within a voxel of it.
    const glm::vec3 p = grid.Center(hit->voxel);
    if (std::abs(p.x) > 2.0f * grid.voxel_size().x) ++crossed;
  }
  EXPECT_GT(tested, 900);
  EXPECT_EQ(crossed, 0);
}

TEST(AvgGrid, MarchHitsTheKnownWallVoxel) {
  auto state = LoadBundled("furnace");
  ASSERT_TRUE(state);
  const VoxelGrid grid = VoxelGrid::Build(*state, 64);
  // The wall x = +1: the first filled voxel along +x from the centre is the
  // one whose x-range contains 1 (conservative: the voxel on the near side
  // when 1 lies on a boundary).
  const auto hit =
      grid.March(glm::vec3(0.0f, 0.1f, -0.2f), glm::vec3(1, 0, 0), glm::vec3(0.0f), false);
  ASSERT_TRUE(hit);
  const float x0 = grid.origin().x + float(hit->voxel.x) * grid.voxel_size().x;
  EXPECT_LE(x0, 1.0f + 1e-5f);
  EXPECT_GE(x0 + grid.voxel_size().x, 1.0f - 1e-5f);
  EXPECT_EQ(hit->voxel.y, grid.VoxelOf({0.0f, 0.1f, -0.2f}).y);
  EXPECT_NEAR(hit->t_enter, x0, 1e-4f);
  // Its data: the inward normal (-x) and albedo 0.5.
  EXPECT_NEAR(grid.Normal(hit->voxel).x, -1.0f, 1e-4f);
  EXPECT_NEAR(grid.Albedo(hit->voxel).g, 0.5f, 1e-6f);
  // The floor y = -1 straight down from (0.3, 0.5, 0.3).
  const auto down = grid.March({0.3f, 0.5f, 0.3f}, {0, -1, 0}, glm::vec3(0.0f), false);
  ASSERT_TRUE(down);
  const float y0 = grid.origin().y + float(down->voxel.y) * grid.voxel_size().y;
  EXPECT_LE(y0, -1.0f + 1e-5f);
  EXPECT_GE(y0 + grid.voxel_size().y, -1.0f - 1e-5f);
}

TEST(AvgGrid, ParallelSurfacesInOneVoxelStayApart) {
  // A lamp 1 cm under a ceiling, both facing down, in one voxel (1.6 cm at
  // 64 voxels over the 1 m room): a path leaving the lamp's back must hit
  // the ceiling in the gap and its VPL stay there, above the lamp. Joined
  // into one slab, a VPL in the gap lay "on" it and its next ray passed
  // through the lamp into the room (issue 29, item 3).
  Material grey;
  grey.base_color_factor = glm::vec4(0.7f, 0.7f, 0.7f, 1.0f);
  const SceneState state(QuadScene({{{0, -0.5f, 0}, {0, 0, 0.5f}, {0.5f, 0, 0}},
                                    {{0, 0.5f, 0}, {0.5f, 0, 0}, {0, 0, 0.5f}},
                                    {{0, 0.49f, 0}, {0.15f, 0, 0}, {0, 0, 0.15f}}},
                                   {grey}));
  const VoxelGrid grid = VoxelGrid::Build(state, 64);
  const glm::vec3 origin(0.01f, 0.49f, 0.02f), up(0, 1, 0);
  ASSERT_EQ(grid.VoxelOf(origin), grid.VoxelOf(origin + 0.0099f * up));
  const auto hit = grid.March(origin, glm::normalize(glm::vec3(0.2f, 1, 0.1f)), up, true);
  ASSERT_TRUE(hit);
  const glm::vec3 p = origin + glm::normalize(glm::vec3(0.2f, 1, 0.1f)) * hit->t_sheet;
  EXPECT_NEAR(p.y, 0.5f, 1e-4f);
  EXPECT_NEAR(hit->sheet_normal.y, -1.0f, 1e-4f);
  const float nudge = 0.05f * glm::length(grid.voxel_size());
  const glm::vec3 vpl =
      grid.KeepInFront(hit->voxel, p + hit->sheet_normal * nudge, origin, up, nudge);
  EXPECT_GT(vpl.y, 0.49f);
  EXPECT_LT(vpl.y, 0.5f);
  // The path's next ray, from that VPL down: it meets the lamp's back.
  // Joined, the VPL lay "on" the one slab and its rays passed the lamp
  // (the leak: second-bounce VPLs on the floor).
  const glm::vec3 down = glm::normalize(glm::vec3(-0.1f, -1, 0.05f));
  const auto back = grid.March(vpl, down, hit->sheet_normal, true);
  ASSERT_TRUE(back);
  EXPECT_NEAR((vpl + down * back->t_sheet).y, 0.49f, 1e-4f);
  EXPECT_NEAR(back->sheet_normal.y, 1.0f, 1e-4f);
  // From below, the lamp is what a ray meets first.
  const auto from_below = grid.March({0.0f, 0.0f, 0.0f}, up, glm::vec3(0.0f), false);
  ASSERT_TRUE(from_below);
  EXPECT_NEAR(from_below->t_sheet, 0.49f, 1e-4f);
}

double Sum(const std::vector<avg::Vpl>& vpls, int bounce, int channel) {
  double s = 0.0;
  for (const avg::Vpl& v : vpls) {
    if (v.bounce == bounce) s += double(v.flux[channel]);
  }
  return s;
}

void ExpectSaneVpls(const std::vector<avg::Vpl>& vpls) {
  for (const avg::Vpl& v : vpls) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(v.flux[c]) && v.flux[c] >= 0.0f);
      ASSERT_TRUE(std::isfinite(v.position[c]));
    }
    ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
  }
}

// A voxel's reflectance is the BRDF's white-sky albedo (issue 18): a
// Lambertian wall (metallic 0, roughness 1) keeps its base colour bitwise
// (dyadic colour: the voxel mean of equal values is exact), a gold wall
// (metallic 1, roughness 0.3) reflects F0 (A - B) + B of the table's
// white-sky (A, B), not its base colour.
TEST(AvgGrid, GlossyVoxelsReflectTheWhiteSkyAlbedo) {
  Material white, gold;
  white.base_color_factor = glm::vec4(0.5f, 0.25f, 0.75f, 1.0f);
  gold.base_color_factor = glm::vec4(1.0f, 0.78f, 0.34f, 1.0f);
  gold.metallic_factor = 1.0f;
  gold.roughness_factor = 0.3f;
  const SceneState state(
      QuadScene({{{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 0}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 1}},
                {white, gold}));
  const glm::vec2 ws = BrdfAlbedoTable::Embedded().WhiteSky(0.3f);
  const glm::vec3 gold_albedo = glm::vec3(gold.base_color_factor) * (ws.x - ws.y) + ws.y;
  const VoxelGrid grid = VoxelGrid::Build(state, 16);
  int white_voxels = 0, gold_voxels = 0;
  glm::ivec3 v;
  for (v.z = 0; v.z < 16; ++v.z) {
    for (v.y = 0; v.y < 16; ++v.y) {
      for (v.x = 0; v.x < 16; ++v.x) {
        if (!grid.Filled(v)) continue;
        const glm::vec3 albedo = grid.Albedo(v);
        const shading::Brdf brdf = grid.Brdf(v);
        if (grid.Center(v).x < 0.0f) {
          ++white_voxels;
          EXPECT_EQ(albedo, glm::vec3(white.base_color_factor));
          EXPECT_TRUE(brdf.Lambertian());
        } else {
          ++gold_voxels;
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(albedo[c], gold_albedo[c], 1e-6f) << c;
          // The VPLs' BRDF: the gold's own parameters.
          EXPECT_EQ(brdf.base_color, glm::vec3(gold.base_color_factor));
          EXPECT_EQ(brdf.metallic, 1.0f);
          EXPECT_NEAR(brdf.roughness, 0.3f, 1e-6f);
        }
      }
    }
  }
  EXPECT_GT(white_voxels, 0);
  EXPECT_GT(gold_voxels, 0);
  // Gold at roughness 0.3 reflects most of F0 (A near 1, B small).
  EXPECT_GT(ws.x, 0.9f);
  EXPECT_LT(ws.y, 0.2f);
}

TEST(AvgVpls, FirstBounceFluxIsLightPowerTimesAlbedoInTheFurnace) {
  // Every surface of the furnace emits L = 1 (power pi L A = 24 pi W) and
  // has albedo 0.5; nothing escapes the closed box, so the first VPLs carry
  // exactly 0.5 x 24 pi in total (up to paths lost at the box's edges).
  auto state = LoadBundled("furnace");
  ASSERT_TRUE(state);
  const VoxelGrid grid = VoxelGrid::Build(*state, 64);
  const auto lights = avg::CollectVplLights(*state, glm::vec3(0.0f), 2.0f);
  avg::VplTraceSettings settings;
  settings.vpls = 1024;
  settings.bounces = 1;
  const avg::VplTraceResult r = avg::TraceVpls(grid, lights, settings);
  const double power = 24.0 * glm::pi<double>();
  EXPECT_NEAR(r.light_power.g, power, 1e-3 * power);
  EXPECT_EQ(r.vpls.size(), 1024u);
  ExpectSaneVpls(r.vpls);
  EXPECT_LE(r.escaped, r.paths / 200) << "paths lost through the shell";
  // 1 %: only the escaped paths are missing (each carries the same flux).
  EXPECT_NEAR(Sum(r.vpls, 1, 1), 0.5 * power, 0.01 * 0.5 * power);

  // Coloured albedo: each channel carries power x its albedo.
  MaterialUpdate colour;
  colour.material = 0;
  colour.base_color = glm::vec4(0.8f, 0.4f, 0.2f, 1.0f);
  state->Apply(colour);
  const VoxelGrid coloured = VoxelGrid::Build(*state, 64);
  const avg::VplTraceResult c = avg::TraceVpls(coloured, lights, settings);
  ExpectSaneVpls(c.vpls);
  for (int ch = 0; ch < 3; ++ch) {
    const double albedo = ch == 0 ? 0.8 : ch == 1 ? 0.4 : 0.2;
    EXPECT_NEAR(Sum(c.vpls, 1, ch), albedo * power, 0.01 * albedo * power) << "channel " << ch;
  }
}

TEST(AvgVpls, DoubleSidedLampUnderACeilingConservesPowerPerBounce) {
  // The closed 1 m room of NearFieldRoomGi (albedo 0.7) with a 30 cm
  // double-sided lamp (albedo 0.78, L = 1) 1 cm under the ceiling: both
  // faces emit, P = 2 pi L A; nothing leaves the room, so the VPLs of
  // bounce b carry between 0.7^b P and 0.78^b P (issue 29, item 3: the
  // VPLs' flux never exceeds what the light emits and the albedos keep).
  // 2 %: the quasi-random paths' share of each surface.
  Material wall, lamp;
  wall.base_color_factor = glm::vec4(0.7f, 0.7f, 0.7f, 1.0f);
  lamp.base_color_factor = glm::vec4(0.78f, 0.78f, 0.78f, 1.0f);
  lamp.emissive_factor = glm::vec3(1.0f);
  lamp.double_sided = true;
  const SceneState state(QuadScene({{{0, -0.5f, 0}, {0, 0, 0.5f}, {0.5f, 0, 0}},
                                    {{0, 0.5f, 0}, {0.5f, 0, 0}, {0, 0, 0.5f}},
                                    {{-0.5f, 0, 0}, {0, 0.5f, 0}, {0, 0, 0.5f}},
                                    {{0.5f, 0, 0}, {0, 0, 0.5f}, {0, 0.5f, 0}},
                                    {{0, 0, -0.5f}, {0.5f, 0, 0}, {0, 0.5f, 0}},
                                    {{0, 0, 0.5f}, {0, 0.5f, 0}, {0.5f, 0, 0}},
                                    {{0, 0.49f, 0}, {0.15f, 0, 0}, {0, 0, 0.15f}, 1}},
                                   {wall, lamp}));
  const VoxelGrid grid = VoxelGrid::Build(state, 64);
  const auto lights = avg::CollectVplLights(state, glm::vec3(0.0f), 1.0f);
  avg::VplTraceSettings settings;
  settings.vpls = 2048;
  settings.bounces = 3;
  settings.roulette = false;
  const avg::VplTraceResult r = avg::TraceVpls(grid, lights, settings);
  const double power = 2.0 * glm::pi<double>() * 0.3 * 0.3;
  EXPECT_NEAR(r.light_power.g, power, 1e-3 * power);
  ExpectSaneVpls(r.vpls);
  EXPECT_EQ(r.escaped, 0u);
  for (int b = 1; b <= 3; ++b) {
    const double flux = Sum(r.vpls, b, 1);
    testing::RecordMeasurement(absl::StrCat("bounce_", b, "_over_power"), flux / power);
    EXPECT_GE(flux, 0.98 * std::pow(0.7, b) * power) << "bounce " << b;
    EXPECT_LE(flux, 1.02 * std::pow(0.78, b) * power) << "bounce " << b;
  }
}

// A 10 cd point light (4 pi 10 W) inside a closed 2 m cube of `material`,
// its VPLs traced with `settings` on a 48^3 grid.
avg::VplTraceResult TracePointLitBox(const Material& material,
                                     const avg::VplTraceSettings& settings) {
  Light point;
  point.type = LightType::kPoint;
  point.intensity = 10.0f;
  const SceneState state(QuadScene(ClosedCube(), {material}, {{point, {0.2f, 0.3f, -0.1f}}}));
  const VoxelGrid grid = VoxelGrid::Build(state, 48);
  const auto lights = avg::CollectVplLights(state, glm::vec3(0.0f), 2.0f);
  EXPECT_EQ(lights.size(), 1u);
  return avg::TraceVpls(grid, lights, settings);
}

// A still view's second set of paths (AvgSolver `still_vpls`) goes on
// with the first set's quasi-random sequence: its path i starts where path
// N + i of one longer trace does (the first bounce depends on the path's
// point only), so the two sets are one sequence, not the same paths twice
// (without the offset every first VPL would repeat the first set's). The
// joined sets weight each VPL by its set's share of the paths: bounce 1
// still carries 0.6 P (1e-3, as one trace), and each bounce's flux is the
// path-weighted mean of the two sets' (1e-5, float rounding).
TEST(AvgVpls, AStillViewsSecondSetContinuesTheSequenceAndJoinsByPathShare) {
  Material grey;
  grey.base_color_factor = glm::vec4(0.6f, 0.6f, 0.6f, 1.0f);
  avg::VplTraceSettings settings;
  settings.vpls = 1024;
  settings.bounces = 3;
  const avg::VplTraceResult a = TracePointLitBox(grey, settings);
  avg::VplTraceSettings second = settings;
  second.sample_offset = a.paths;
  const avg::VplTraceResult b = TracePointLitBox(grey, second);
  avg::VplTraceSettings longer = settings;
  longer.vpls = 4096;
  const avg::VplTraceResult c = TracePointLitBox(grey, longer);
  ASSERT_GT(a.paths, 100u);
  ASSERT_EQ(b.paths, a.paths);
  ASSERT_GE(c.paths, a.paths + b.paths);
  size_t same_as_longer = 0, same_as_first = 0;
  for (size_t i = 0; i < b.paths; ++i) {
    const glm::vec3 p = b.vpls[b.path_first[i]].position;
    same_as_longer += p == c.vpls[c.path_first[a.paths + i]].position ? 1 : 0;
    same_as_first += p == a.vpls[a.path_first[i]].position ? 1 : 0;
  }
  EXPECT_EQ(same_as_longer, size_t(b.paths));
  EXPECT_EQ(same_as_first, 0u);

  const avg::VplTraceResult joined = avg::JoinTraces(a, b);
  ExpectSaneVpls(joined.vpls);
  ASSERT_EQ(joined.vpls.size(), a.vpls.size() + b.vpls.size());
  EXPECT_EQ(joined.paths, a.paths + b.paths);
  ASSERT_EQ(joined.path_first.size(), a.path_first.size() + b.path_first.size());
  EXPECT_EQ(joined.path_first[a.path_first.size()], uint32_t(a.vpls.size()));
  const double power = 4.0 * glm::pi<double>() * 10.0;
  EXPECT_NEAR(Sum(joined.vpls, 1, 0), 0.6 * power, 1e-3 * power);
  const double wa = double(a.paths) / double(joined.paths);
  for (int bounce = 1; bounce <= 3; ++bounce) {
    const double mean = wa * Sum(a.vpls, bounce, 0) + (1.0 - wa) * Sum(b.vpls, bounce, 0);
    EXPECT_NEAR(Sum(joined.vpls, bounce, 0), mean, 1e-5 * power) << "bounce " << bounce;
  }
}

TEST(AvgVpls, PointLightInAClosedBox) {
  // A 10 cd point light inside a closed albedo-0.6 cube: 4 pi 10 W leave
  // the light, 0.6 of it is in the first VPLs; later bounces carry
  // 0.6^k of it on average (roulette keeps them unbiased), within
  // Monte-Carlo tolerance.
  Material grey;
  grey.base_color_factor = glm::vec4(0.6f, 0.6f, 0.6f, 1.0f);
  avg::VplTraceSettings settings;
  settings.vpls = 2048;
  settings.bounces = 3;
  const avg::VplTraceResult r = TracePointLitBox(grey, settings);
  ExpectSaneVpls(r.vpls);
  const double power = 4.0 * glm::pi<double>() * 10.0;
  EXPECT_EQ(r.escaped, 0u);
  EXPECT_NEAR(Sum(r.vpls, 1, 0), 0.6 * power, 1e-3 * power);  // every path hits once
  // Roulette: bounce 2 is a random-length estimate; several standard errors.
  EXPECT_NEAR(Sum(r.vpls, 2, 0), 0.36 * power, 0.05 * 0.36 * power);
  EXPECT_NEAR(Sum(r.vpls, 3, 0), 0.216 * power, 0.08 * 0.216 * power);
}

// A point light in a closed box of rough metal (base 0.9, metallic 1,
// roughness 0.5): glossy VPLs send their paths on by sampling the BRDF
// (ggx.h Sample) for the light they received, weighted f cos / (pdf
// a(v)), whose mean is 1, so bounce b still carries P a^b on average, a
// the white-sky albedo the voxels reflect (issue 29, item 6). Every VPL
// records where its light came from, in front of its surface, and the
// metal's BRDF. Without the 1 / a(v) the flux of bounce 2 is a(v) lower
// (about 0.9x); with cosine sampling and no BRDF weight it is the same,
// so the test holds the lobe's direction too: the ray after a bounce
// leaves near the mirror direction (mean cosine to it 0.82; cosine
// sampling gives 2/3 of the incident cosine on average, about 0.45).
TEST(AvgVpls, GlossyVplsReflectThroughTheBrdfAndKeepTheAlbedoPerBounce) {
  Material metal;
  metal.base_color_factor = glm::vec4(0.9f, 0.9f, 0.9f, 1.0f);
  metal.metallic_factor = 1.0f;
  metal.roughness_factor = 0.5f;
  avg::VplTraceSettings settings;
  settings.vpls = 4096;
  settings.bounces = 3;
  settings.roulette = false;
  settings.tail_bound = 0.0;
  const avg::VplTraceResult r = TracePointLitBox(metal, settings);
  ExpectSaneVpls(r.vpls);
  EXPECT_EQ(r.escaped, 0u);
  const float a = BrdfWhiteSkyAlbedo(glm::vec3(0.9f), 1.0f, 0.5f).g;
  const double power = 4.0 * glm::pi<double>() * 10.0;
  for (int b = 1; b <= 3; ++b) {
    const double flux = Sum(r.vpls, b, 1), expected = std::pow(double(a), b) * power;
    testing::RecordMeasurement(absl::StrCat("bounce_", b, "_over_expected"), flux / expected);
    EXPECT_NEAR(flux, expected, (b == 1 ? 1e-3 : 0.03) * expected) << "bounce " << b;
  }
  double mirror_cosine = 0.0;
  int pairs = 0;
  for (size_t i = 0; i + 1 < r.vpls.size(); ++i) {
    const avg::Vpl& v = r.vpls[i];
    EXPECT_GT(glm::dot(v.incident, v.normal), 0.0f);
    EXPECT_EQ(v.brdf.metallic, 1.0f);
    EXPECT_NEAR(v.brdf.roughness, 0.5f, 1e-6f);
    const avg::Vpl& next = r.vpls[i + 1];
    if (next.bounce != v.bounce + 1) continue;
    const glm::vec3 mirror = 2.0f * glm::dot(v.incident, v.normal) * v.normal - v.incident;
    mirror_cosine += double(glm::dot(mirror, -next.incident));
    ++pairs;
  }
  ASSERT_GT(pairs, 1000);
  testing::RecordMeasurement("mean_cosine_to_mirror", mirror_cosine / pairs);
  EXPECT_GT(mirror_cosine / pairs, 0.7);
}

TEST(AvgVpls, SpotSolidAngleOfAHardCone) {
  // Inner = outer: falloff 1 inside the cone, so Omega ~ 2 pi (1 - cos).
  const float cos_outer = std::cos(0.5f);
  const float scale = 1.0f / 0.001f;  // KHR: 1 / max(0.001, cos_inner - cos_outer)
  const float omega = avg::SpotSolidAngle(scale, -cos_outer * scale, cos_outer);
  // The falloff still ramps over the last 0.001 of cos(theta): f^2 there
  // integrates to 0.001 / 3.
  EXPECT_NEAR(omega, 2.0f * glm::pi<float>() * (1.0f - cos_outer - 0.001f + 0.001f / 3.0f), 1e-4f);
}

TEST(AvgVpls, SameVplsEveryFrameAndForAnyThreadCount) {
  auto state = LoadBundled("cornell_box");
  ASSERT_TRUE(state);
  const VoxelGrid grid = VoxelGrid::Build(*state, 64);
  const auto lights = avg::CollectVplLights(*state, glm::vec3(0.3f), 1.0f);
  avg::VplTraceSettings one;
  one.vpls = 512;
  one.threads = 1;
  avg::VplTraceSettings two = one;
  two.threads = 2;
  const avg::VplTraceResult a = avg::TraceVpls(grid, lights, one);
  const avg::VplTraceResult b = avg::TraceVpls(grid, lights, two);
  ASSERT_EQ(a.vpls.size(), b.vpls.size());
  EXPECT_EQ(a.paths, b.paths);
  for (size_t i = 0; i < a.vpls.size(); ++i) {
    ASSERT_EQ(a.vpls[i].position, b.vpls[i].position) << i;
    ASSERT_EQ(a.vpls[i].flux, b.vpls[i].flux) << i;
  }
  ExpectSaneVpls(a.vpls);
}

TEST(AvgVpls, ScrambledHaltonIsInUnitIntervalAndWellSpread) {
  const avg::ScrambledHalton& h = avg::ScrambledHalton::Instance();
  for (int d = 0; d < avg::ScrambledHalton::kMaxDimensions; ++d) {
    double mean = 0.0;
    for (uint64_t i = 0; i < 1024; ++i) {
      const float u = h.Get(i, d);
      ASSERT_GE(u, 0.0f);
      ASSERT_LT(u, 1.0f);
      mean += u;
    }
    // A low-discrepancy sequence's mean converges much faster than 1/sqrt(N).
    EXPECT_NEAR(mean / 1024.0, 0.5, 0.01) << "dimension " << d;
  }
}

}  // namespace avg_grid_test
}  // namespace gistream
