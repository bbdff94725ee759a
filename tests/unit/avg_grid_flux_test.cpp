// `avg`'s light paths lose no flux at any grid size or scene scale
// (issue 14): in the closed furnace every path's first ray hits a wall, so
// the first-bounce VPLs carry light power x albedo, whatever the grid
// resolution (16 ... 128) and whether the box is scaled to millimetres or
// kilometres.
#include <cmath>
#include <memory>
#include <string>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "support/measurement.h"

#include "scene/gltf/gltf_import.h"
#include "solvers/avg/voxel_grid.h"
#include "solvers/avg/vpl_lights.h"
#include "solvers/avg/vpl_tracer.h"

namespace gistream {
namespace avg_grid_flux_test {

std::unique_ptr<SceneState> ScaledFurnace(float scale) {
  auto scene = ImportSceneByName(std::string(GISTREAM_SOURCE_DIR "/scenes"), "furnace", {});
  EXPECT_TRUE(scene.ok()) << scene.status();
  if (!scene.ok()) return nullptr;
  for (Node& node : scene->nodes) {
    if (node.mesh >= 0) node.scale *= scale;
  }
  return std::make_unique<SceneState>(std::make_shared<const Scene>(*std::move(scene)));
}

double FirstBounceFlux(const std::vector<avg::Vpl>& vpls) {
  double sum = 0.0;
  for (const avg::Vpl& v : vpls) sum += v.bounce == 1 ? double(v.flux.g) : 0.0;
  return sum;
}

TEST(AvgGridFlux, FirstBounceFluxIsLightPowerTimesAlbedoAtEveryGridSizeAndScale) {
  for (float scale : {1e-4f, 1e-3f, 1.0f, 1e3f}) {
    auto state = ScaledFurnace(scale);
    ASSERT_TRUE(state);
    for (int n : {16, 32, 64, 128}) {
      const avg::VoxelGrid grid = avg::VoxelGrid::Build(*state, n);
      const auto lights = avg::CollectVplLights(*state, glm::vec3(0.0f), 2.0f * scale);
      avg::VplTraceSettings settings;
      settings.vpls = 4096;
      settings.bounces = 1;
      const avg::VplTraceResult r = avg::TraceVpls(grid, lights, settings);
      ASSERT_GT(r.paths, 0u);
      const double ratio = FirstBounceFlux(r.vpls) / (0.5 * double(r.light_power.g));
      const std::string name = absl::StrCat("scale_", scale, "_grid_", n);
      testing::RecordMeasurement(name + "_flux_over_expected", ratio);
      testing::RecordMeasurement(name + "_escaped", double(r.escaped));
      EXPECT_EQ(r.escaped, 0u) << name;
      EXPECT_NEAR(ratio, 1.0, 1e-4) << name;
    }
  }
}

}  // namespace avg_grid_flux_test
}  // namespace gistream
