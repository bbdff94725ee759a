// `antiradiance` on a glossy floor end to end on llvmpipe: the display
// shows the glossy leaves' exitant radiance toward the camera from their
// directional bins (solvers/antiradiance/glossy_transfer.h), so the floor's
// indirect light depends on where it is seen from: bright where its mirror
// direction meets a lit wall, dark where it meets the empty sky.
#include <gtest/gtest.h>

#include "support/gltf_builder.h"
#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace antiradiance_glossy_test {

using testing::FloatImage;
using testing::GltfBuilder;

constexpr uint32_t kSize = 32;

// Mean green over the central 8 x 8 pixels of `image` minus `direct`'s.
double CentralIndirect(const FloatImage& image, const FloatImage& direct) {
  double sum = 0.0;
  for (int y = 12; y < 20; ++y) {
    for (int x = 12; x < 20; ++x) sum += image.at(x, y)[1] - direct.at(x, y)[1];
  }
  return sum / 64.0;
}

TEST(AntiradianceGlossyDisplay, FloorReflectsTheLitWallTowardTheMirrorDirection) {
  // A white metal floor (roughness 0.45, what 128 bins resolve), a white
  // diffuse wall at x = -1 facing +x, a point light in front of the wall.
  // Both views look at the floor point (0.3, 0, 0): from (1.2, 0.5, 0) its
  // mirror direction climbs toward the lit wall (meeting it 0.72 m up);
  // from straight above it points at the empty sky. The direct light of
  // each view (the `direct` solver, the same per-pixel BRDF) is subtracted.
  GltfBuilder b;
  const int metal = b.AddMaterial("metal", {1, 1, 1});
  b.SetMetallicRoughness(metal, 1.0f, 0.45f);
  const int white = b.AddMaterial("white", {0.8f, 0.8f, 0.8f});
  b.AddQuad("floor", {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, metal, 8);
  b.AddQuad("wall", {-1, 1, 0}, {0, 1, 0}, {0, 0, 1}, white, 8);
  b.AddPointLight("lamp", {-0.3f, 1.2f, 0.0f}, {1, 1, 1}, 5.0f);
  b.AddCamera("camera", {1.2f, 0.5f, 0.0f}, {-0.87f, -0.49f, 0.0f}, {0, 1, 0}, 0.6f);
  auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(b.ToJson()));
  ASSERT_TRUE(info.ok()) << info.status();
  CameraUpdate grazing, above;
  grazing.look_at = LookAt{{1.2f, 0.5f, 0.0f}, {0.3f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  above.look_at = LookAt{{0.3f, 1.5f, 0.0f}, {0.3f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}};
  for (CameraUpdate* c : {&grazing, &above}) c->yfov_degrees = 30.0f;
  auto render = [&](const char* solver, const CameraUpdate& camera) {
    return testing::RenderExr(testing::SharedEngine(), info->id, solver, kSize, kSize, {}, camera);
  };
  const FloatImage ar_grazing = render("antiradiance", grazing);
  const FloatImage ar_above = render("antiradiance", above);
  ASSERT_EQ(ar_grazing.width, int(kSize));
  EXPECT_EQ(ar_grazing.non_finite(), 0u);
  EXPECT_EQ(ar_above.non_finite(), 0u);
  const double toward_wall = CentralIndirect(ar_grazing, render("direct", grazing));
  const double toward_sky = CentralIndirect(ar_above, render("direct", above));
  testing::RecordMeasurement("indirect_toward_wall", toward_wall);
  testing::RecordMeasurement("indirect_toward_sky", toward_sky);
  EXPECT_GT(toward_wall, 0.01);
  EXPECT_GT(toward_wall, 3.0 * std::max(toward_sky, 0.0));
  EXPECT_TRUE(testing::SharedEngine().UnloadScene(info->id).ok());
}

}  // namespace antiradiance_glossy_test
}  // namespace gistream
