// An emitter emits on the side its authored normals face, and from both
// faces when its material is doubleSided (glTF 2.0 3.9.2; render/
// area_lights.cpp, pathtrace). The view shows the same: seen from behind,
// a one-sided lamp is a dark surface (its back face reflects, it does not
// emit), in every solver; before, the G-buffer wrote L_e on back faces too,
// so the rasterizing solvers showed the lamp lit from both sides where
// pathtrace showed it black. A lone quad of L_e = 1 (albedo 0.5, nothing
// else to light its back): the centre pixel is 1 from the front, 0 from
// behind, and 1 from behind once the material is doubleSided.
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "support/gltf_builder.h"
#include "support/registered_solvers.h"
#include "support/render_helpers.h"

namespace gistream {
namespace emitter_faces_test {

constexpr uint32_t kSize = 16;

double CentreSeenFrom(const std::string& scene, const std::string& solver, float z) {
  CameraUpdate camera;
  camera.look_at = LookAt{{0.0f, 0.0f, z}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  RenderRequest request = testing::SolverRequest(scene, solver, {}, kSize);
  request.camera = camera;
  const testing::FloatImage image = testing::RenderRequestExr(request);
  EXPECT_EQ(image.non_finite(), 0u);
  return image.width == int(kSize) ? double(image.at(kSize / 2, kSize / 2).g) : -1.0;
}

class EmitterFaces : public ::testing::TestWithParam<std::string> {};

TEST_P(EmitterFaces, AOneSidedLampIsDarkFromBehind) {
  const std::string& solver = GetParam();
  for (const bool double_sided : {false, true}) {
    SCOPED_TRACE(double_sided ? "doubleSided" : "one-sided");
    testing::GltfBuilder b;
    const int lamp = b.AddMaterial("lamp", {0.5f, 0.5f, 0.5f}, {1.0f, 1.0f, 1.0f});
    if (double_sided) b.SetDoubleSided(lamp);
    // Normal +Z (cross(u, v)).
    b.AddQuad("lamp", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, lamp);
    b.AddCamera("camera", {0, 0, 2}, {0, 0, -1}, {0, 1, 0}, 0.5f);
    const testing::TestScene scene(testing::SceneFromBytes(b.ToJson()));
    ASSERT_FALSE(scene.id().empty());
    EXPECT_NEAR(CentreSeenFrom(scene.id(), solver, 2.0f), 1.0, 1e-3) << solver;
    EXPECT_NEAR(CentreSeenFrom(scene.id(), solver, -2.0f), double_sided ? 1.0 : 0.0, 1e-3)
        << solver;
  }
}

INSTANTIATE_TEST_SUITE_P(EverySolver, EmitterFaces,
                         ::testing::ValuesIn(testing::RegisteredSolverNames()),
                         [](const auto& p) { return p.param; });

}  // namespace emitter_faces_test
}  // namespace gistream
