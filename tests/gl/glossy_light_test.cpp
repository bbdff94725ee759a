// Glossy surfaces light the room by their BRDF (issue 29, item 6). In
// glossy_box a spot lights a gold GGX cube (metallic 1, roughness 0.3) in
// a diffuse room; the cube's reflection is about 28 % of the light on the
// walls and floor the camera sees, most of it thrown forward onto the
// floor by the cube's faces. Shading the cube as a gold Lambertian surface
// in the solvers' indirect light sends that light everywhere alike: the
// room came out 0.87x (sh_probes) and 0.86x (avg) of the reference, the
// floor in front of the cube at half. Now sh_probes' cube maps shade
// glossy texels towards their probe (render_cubemaps.comp.glsl) and
// avg's VPLs on the cube reflect through the BRDF
// (avg/illuminate.frag.glsl, vpl_tracer.cpp), and every GI solver that
// does must hold the room's mean to 5 % of pathtrace's at its defaults.
//
// The room: every pixel that is not the cube (those where a path-traced
// copy with a black cube is not black), 32 px, luminance. The reference,
// 1024 spp, is within 0.3 % of itself over seeds here.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

#include "support/measurement.h"
#include "support/registered_solvers.h"
#include "support/render_helpers.h"

namespace gistream {
namespace glossy_light_test {

using testing::FloatImage;

constexpr uint32_t kSize = 32;

double Luminance(const glm::vec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

FloatImage RenderScene(const std::string& scene, const std::string& solver,
                       std::map<std::string, std::string> params) {
  RenderRequest request;
  request.scene = scene;
  request.solver = solver;
  request.params = std::move(params);
  request.width = request.height = kSize;
  return testing::RenderRequestExr(std::move(request));
}

// The pixels that see the room: those where a copy of glossy_box with the
// cube black does not render black (the cube is in front elsewhere). Once
// per binary.
std::vector<bool> ComputeRoomPixels() {
  std::ifstream in(GISTREAM_SOURCE_DIR "/scenes/glossy_box.gltf", std::ios::binary);
  nlohmann::json doc = nlohmann::json::parse(in);
  for (nlohmann::json& m : doc["materials"]) {
    if (m["name"] == "gold") {
      m["pbrMetallicRoughness"] = {
          {"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}};
    }
  }
  std::vector<bool> room(size_t(kSize) * kSize);
  auto black = testing::SharedEngine().LoadScene(testing::SceneFromBytes(doc.dump()));
  EXPECT_TRUE(black.ok()) << black.status();
  if (!black.ok()) return room;
  const FloatImage mask = RenderScene(black->id, "pathtrace", {{"spp", "256"}});
  (void)testing::SharedEngine().UnloadScene(black->id);
  for (int y = 0; y < int(kSize); ++y) {
    for (int x = 0; x < int(kSize); ++x) {
      room[size_t(y) * kSize + size_t(x)] = Luminance(mask.at(x, y)) > 0.0;
    }
  }
  return room;
}

// The mean luminance of the room's pixels.
double Room(const FloatImage& image) {
  static const auto* const room = new std::vector<bool>(ComputeRoomPixels());
  double sum = 0.0;
  int count = 0;
  for (int y = 0; y < int(kSize); ++y) {
    for (int x = 0; x < int(kSize); ++x) {
      if (!(*room)[size_t(y) * kSize + size_t(x)]) continue;
      sum += Luminance(image.at(x, y));
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

class GlossyLight : public ::testing::TestWithParam<const char*> {
 protected:
  static void SetUpTestSuite() {
    glossy_ = new testing::BundledCopy("glossy_box.gltf");
    reference_ = new FloatImage(RenderScene(glossy_->id(), "pathtrace", {{"spp", "1024"}}));
  }
  static void TearDownTestSuite() {
    delete reference_;
    delete glossy_;
    reference_ = nullptr;
    glossy_ = nullptr;
  }

  static testing::BundledCopy* glossy_;
  static FloatImage* reference_;
};
testing::BundledCopy* GlossyLight::glossy_ = nullptr;
FloatImage* GlossyLight::reference_ = nullptr;

// Measured: sh_probes 0.995x, avg 0.960x, antiradiance 0.979x (its glossy
// leaves; 1.039x before its near links were split per piece of the
// sender), implicit_visibility 0.981x (its glossy elements' bins; 0.90x
// when they reflected diffusely with their white-sky albedo).
TEST_P(GlossyLight, TheRoomMatchesTheReferenceAtTheDefaults) {
  const std::string solver = GetParam();
  const FloatImage image = RenderScene(glossy_->id(), solver, {});
  ASSERT_EQ(image.width, int(kSize));
  EXPECT_EQ(image.non_finite(), 0u);
  const double got = Room(image), want = Room(*reference_);
  ASSERT_GT(want, 0.0) << "no room pixels, or a black reference";
  testing::RecordMeasurement("room_over_reference", got / want);
  EXPECT_NEAR(got, want, 0.05 * want) << solver << ": " << got / want << "x";
  // The whole picture, cube included. avg: 0.106 when its VPLs reflected
  // diffusely, 0.25 leaves room for VPL placement and the reference's own
  // noise (pathtrace at 386 spp is 0.34 from a 1024-spp one here); shading
  // the cube Lambertian with its base colour was 25.
  const double relmse = testing::RelMse(image, *reference_);
  testing::RecordMeasurement("relmse", relmse);
  EXPECT_LT(relmse, 0.25) << solver;
}

const std::vector<const char*> kGlossyLightSolvers = {"sh_probes", "avg", "antiradiance",
                                                      "implicit_visibility"};

INSTANTIATE_TEST_SUITE_P(Solvers, GlossyLight, ::testing::ValuesIn(kGlossyLightSolvers));

TEST(GlossyLightCoverage, CoversEveryRegisteredSolver) {
  testing::ExpectCoversEveryRegisteredSolver(
      {kGlossyLightSolvers.begin(), kGlossyLightSolvers.end()},
      {{"direct", "no indirect light: the room is 0.63x"}, {"pathtrace", "the reference"}});
}

// The GI solvers' own elements re-emit with the material's dielectric F0
// and F90 (KHR_materials_ior, KHR_materials_specular; issue 29, item 1),
// not the default ior 1.5. glossy_box with the gold cube made a dark
// dielectric (base colour 0.05, roughness 0.3) of ior 10: F0 = (9/11)^2 =
// 0.67 where the default is 0.04, so nearly all the light the cube sends
// into the room is its specular lobe. The room's mean luminance against
// pathtrace's (1024 spp), the cube's pixels left out as above.
FloatImage HighIorCubeRender(const std::string& solver, std::map<std::string, std::string> params) {
  std::ifstream in(GISTREAM_SOURCE_DIR "/scenes/glossy_box.gltf", std::ios::binary);
  nlohmann::json doc = nlohmann::json::parse(in);
  for (nlohmann::json& m : doc["materials"]) {
    if (m["name"] != "gold") continue;
    m["pbrMetallicRoughness"] = {{"baseColorFactor", {0.05, 0.05, 0.05, 1}},
                                 {"metallicFactor", 0},
                                 {"roughnessFactor", 0.3}};
    m["extensions"] = {{"KHR_materials_ior", {{"ior", 10.0}}}};
  }
  doc["extensionsUsed"].push_back("KHR_materials_ior");
  auto scene = testing::SharedEngine().LoadScene(testing::SceneFromBytes(doc.dump()));
  EXPECT_TRUE(scene.ok()) << scene.status();
  if (!scene.ok()) return {};
  FloatImage image = RenderScene(scene->id, solver, std::move(params));
  (void)testing::SharedEngine().UnloadScene(scene->id);
  return image;
}

// The 1024-spp reference, once per binary.
const FloatImage& HighIorCubeReference() {
  static const FloatImage* reference =
      new FloatImage(HighIorCubeRender("pathtrace", {{"spp", "1024"}}));
  return *reference;
}

class GlossyDielectricLight : public ::testing::TestWithParam<const char*> {};

// Measured: antiradiance 0.984x, sh_probes 0.998x, avg 0.961x,
// implicit_visibility 0.986x; with the default F0 at antiradiance's glossy
// leaves, sh_probes' probe texels and avg's VPLs: 0.832x, 0.788x, 0.943x;
// implicit_visibility's elements reflecting diffusely (white-sky albedo
// with the material's F0): 0.83x.
TEST_P(GlossyDielectricLight, ReEmitsWithTheMaterialsFresnel) {
  const std::string solver = GetParam();
  const FloatImage& reference = HighIorCubeReference();
  ASSERT_EQ(reference.width, int(kSize));
  const FloatImage image = HighIorCubeRender(solver, {});
  ASSERT_EQ(image.width, int(kSize));
  EXPECT_EQ(image.non_finite(), 0u);
  const double got = Room(image), want = Room(reference);
  ASSERT_GT(want, 0.0) << "no room pixels, or a black reference";
  testing::RecordMeasurement("over_reference", got / want);
  EXPECT_NEAR(got, want, 0.05 * want) << solver << ": " << got / want << "x";
}

const std::vector<const char*> kDielectricSolvers = {"antiradiance", "sh_probes", "avg",
                                                     "implicit_visibility"};

INSTANTIATE_TEST_SUITE_P(Solvers, GlossyDielectricLight, ::testing::ValuesIn(kDielectricSolvers));

TEST(GlossyDielectricLightCoverage, CoversEveryRegisteredSolver) {
  testing::ExpectCoversEveryRegisteredSolver(
      {kDielectricSolvers.begin(), kDielectricSolvers.end()},
      {{"direct", "no indirect light"}, {"pathtrace", "the reference"}});
}

}  // namespace glossy_light_test
}  // namespace gistream
