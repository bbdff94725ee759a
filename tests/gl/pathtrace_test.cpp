// The reference path tracer against closed forms (white furnace, inverse
// square law) and against `direct` on the Cornell box. Stochastic output is
// judged by means over many samples with tolerances several standard
// errors wide.
#include <cmath>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "scene/gltf_import.h"
#include "support/gltf_builder.h"
#include "support/render_helpers.h"

namespace gistream {
namespace {

using testing::FloatImage;

constexpr float kPi = 3.14159265358979f;

std::string ReadScene(const std::string& name) {
  std::ifstream in(std::string(GISTREAM_SOURCE_DIR) + "/scenes/" + name, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A private copy of a bundled scene (uploaded as bytes), so material
// changes do not leak into other tests.
std::string LoadCopy(const std::string& file) {
  auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(ReadScene(file)));
  EXPECT_TRUE(info.ok()) << info.status();
  return info.ok() ? info->id : "";
}

double Stat(const EncodedFrame& frame, const std::string& name) {
  for (const auto& [k, v] : frame.stats) {
    if (k == name) return v;
  }
  ADD_FAILURE() << "no stat " << name;
  return -1.0;
}

glm::dvec3 Mean(const FloatImage& image) {
  glm::dvec3 sum(0.0);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) sum += glm::dvec3(image.at(x, y));
  }
  return sum / double(image.width * image.height);
}

FloatImage Render(const std::string& scene, std::map<std::string, std::string> params,
                  uint32_t size, std::vector<Update> updates = {}, EncodedFrame* frame = nullptr) {
  RenderRequest request;
  request.scene = scene;
  request.solver = "pathtrace";
  request.params = std::move(params);
  request.width = request.height = size;
  request.encoding.format = ImageFormat::kExr;
  request.updates = std::move(updates);
  auto result = testing::SharedEngine().Render(request);
  EXPECT_TRUE(result.ok()) << result.status();
  if (!result.ok()) return {};
  if (frame) *frame = *result;
  return testing::DecodeExr(*result);
}

TEST(Pathtrace, WhiteFurnaceHalfAlbedo) {
  // Closed box, albedo 0.5, emission 1: L = E / (1 - rho) = 2 everywhere.
  const std::string id = LoadCopy("furnace.gltf");
  EncodedFrame frame;
  const FloatImage image = Render(id, {{"spp", "64"}}, 16, {}, &frame);
  ASSERT_EQ(image.width, 16);
  EXPECT_EQ(image.non_finite(), 0u);
  const glm::dvec3 mean = Mean(image);
  // 16k paths; the per-path standard deviation is about 1, so the standard
  // error is about 0.008 (0.4 %): 1 % is more than two of them.
  EXPECT_NEAR(mean.g, 2.0, 0.02);
  EXPECT_NEAR(mean.r, mean.b, 1e-9);
  EXPECT_EQ(Stat(frame, "nonfinite_samples"), 0.0);
}

TEST(Pathtrace, WhiteFurnaceStiffAlbedo) {
  // rho = 0.9: L = 10. Paths are long (about 10 bounces on average).
  const std::string id = LoadCopy("furnace.gltf");
  MaterialUpdate albedo;
  albedo.material = 0;
  albedo.base_color = glm::vec4(0.9f, 0.9f, 0.9f, 1.0f);
  const FloatImage image = Render(id, {{"spp", "256"}}, 16, {{1, albedo}});
  ASSERT_EQ(image.width, 16);
  EXPECT_EQ(image.non_finite(), 0u);
  EXPECT_NEAR(Mean(image).g, 10.0, 0.2);
}

TEST(Pathtrace, PointLightOverPlane) {
  // L = rho / pi * I cos(theta) / r^2; one plane, so nothing bounces back.
  const float albedo = 0.6f, intensity = 8.0f, height = 1.5f;
  testing::GltfBuilder b;
  const int mat = b.AddMaterial("plane", {albedo, albedo, albedo});
  b.AddQuad("plane", {0, 0, 0}, {0, 0, 20}, {20, 0, 0}, mat, 2);
  b.AddPointLight("lamp", {0.0f, height, 0.0f}, {1, 1, 1}, intensity);
  b.AddCamera("camera", {0.0f, 1.0f, 0.0f}, {0, -1, 0}, {0, 0, -1}, 1.2f);
  auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(b.ToJson()));
  ASSERT_TRUE(info.ok()) << info.status();
  const FloatImage image = Render(info->id, {{"spp", "4"}}, 32);
  ASSERT_EQ(image.width, 32);
  ViewCamera camera;
  camera.position = {0.0f, 1.0f, 0.0f};
  camera.rotation = glm::quat_cast(glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0)));
  camera.yfov = 1.2f;
  camera.width = camera.height = 32;
  const glm::mat4 inv = glm::inverse(camera.Projection() * camera.View());
  for (const glm::ivec2 px : {glm::ivec2(16, 16), glm::ivec2(3, 16), glm::ivec2(28, 4),
                              glm::ivec2(6, 27)}) {
    const glm::vec2 ndc((float(px.x) + 0.5f) / 32.0f * 2.0f - 1.0f,
                        1.0f - (float(px.y) + 0.5f) / 32.0f * 2.0f);
    const glm::vec4 far = inv * glm::vec4(ndc, 0.5f, 1.0f);
    const glm::vec3 dir = glm::normalize(glm::vec3(far) / far.w - camera.position);
    const glm::vec3 p = camera.position + dir * (camera.position.y / -dir.y);
    const glm::vec3 d = glm::vec3(0.0f, height, 0.0f) - p;
    const float r2 = glm::dot(d, d);
    const float expected = albedo / kPi * intensity * (height / std::sqrt(r2)) / r2;
    EXPECT_NEAR(image.at(px.x, px.y).g, expected, 0.02f * expected) << px.x << "," << px.y;
  }
}

class PathtraceCornell : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string id = LoadCopy("cornell_box.gltf");
    auto scene = ImportSceneByName(std::string(GISTREAM_SOURCE_DIR) + "/scenes", "cornell_box", {});
    ASSERT_TRUE(scene.ok()) << scene.status();
    state_ = std::make_unique<SceneState>(std::make_shared<const Scene>(*std::move(scene)));
    camera_ = DefaultCamera(*state_, kSize, kSize);
    reference_ = Render(id, {{"spp", "256"}}, kSize);
    // max_depth 1: emission plus next-event estimation at the first hit,
    // i.e. exactly the direct light, computed independently of `direct`.
    reference_direct_ = Render(id, {{"spp", "256"}, {"max_depth", "1"}}, kSize);
    direct_ = testing::RenderExr(testing::SharedEngine(), id, "direct", kSize, kSize);
  }
  static glm::vec3 Mean(const FloatImage& image, const glm::vec3& world, int r) {
    const glm::ivec2 p = testing::Project(camera_, world);
    return image.mean(p.x, p.y, r);
  }
  static constexpr uint32_t kSize = 64;
  static inline std::unique_ptr<SceneState> state_;
  static inline ViewCamera camera_;
  static inline FloatImage reference_, reference_direct_, direct_;
};

TEST_F(PathtraceCornell, AgreesWithDirectOnTheEmitter) {
  // The emitter's pixels are its 17-nit emission plus the little light the
  // room reflects onto it: both solvers must show the same emission.
  const glm::vec3 pt = Mean(reference_, {0.278f, 0.548f, 0.2795f}, 0);
  const glm::vec3 d = Mean(direct_, {0.278f, 0.548f, 0.2795f}, 0);
  EXPECT_NEAR(pt.g, d.g, 0.03f * d.g);
}

TEST_F(PathtraceCornell, DirectLightAgreesWithDirect) {
  // The reference's direct light (max_depth 1) against `direct` on lit
  // surfaces. 5 %: `direct` uses 64 stratified emitter samples and shadow
  // maps, the reference 256 spp (its standard error over a 5x5 window is
  // about 1 %); shadow edges are avoided.
  for (const glm::vec3 p : {glm::vec3(0.45f, 0.0f, 0.12f), glm::vec3(0.001f, 0.3f, 0.3f),
                            glm::vec3(0.3f, 0.3f, 0.559f), glm::vec3(0.555f, 0.3f, 0.3f)}) {
    const glm::vec3 c_pt = Mean(reference_direct_, p, 2);
    const glm::vec3 c_d = Mean(direct_, p, 2);
    const float pt = c_pt.r + c_pt.g + c_pt.b, d = c_d.r + c_d.g + c_d.b;
    EXPECT_GT(d, 0.03f) << p.x << "," << p.y << "," << p.z;
    EXPECT_NEAR(d, pt, 0.05f * pt) << p.x << "," << p.y << "," << p.z;
  }
}

TEST_F(PathtraceCornell, IndirectAddsToDirectOnLitFloor) {
  // On the open floor indirect light adds about 40 % to the direct light
  // (measured: 0.174 vs 0.122 at 256 spp): more than nothing, less than the
  // direct light itself.
  const glm::vec3 pt = Mean(reference_, {0.45f, 0.0f, 0.12f}, 2);
  const glm::vec3 d = Mean(direct_, {0.45f, 0.0f, 0.12f}, 2);
  EXPECT_GT(pt.r, 1.1f * d.r);
  EXPECT_LT(pt.r, 2.0f * d.r);
}

TEST_F(PathtraceCornell, IndirectOnlyRegionsAreBrighterInTheReference) {
  // The ceiling gets no direct light (the emitter faces down).
  const glm::vec3 ceiling_pt = Mean(reference_, {0.12f, 0.5488f, 0.45f}, 1);
  const glm::vec3 ceiling_d = Mean(direct_, {0.12f, 0.5488f, 0.45f}, 1);
  EXPECT_LT(ceiling_d.r, 1e-3f);
  EXPECT_GT(ceiling_pt.r, 0.02f);
  // The floor in the tall block's shadow (see DirectCornellTest).
  const glm::vec3 shadow_pt = Mean(reference_, {0.50f, 0.0f, 0.35f}, 1);
  const glm::vec3 shadow_d = Mean(direct_, {0.50f, 0.0f, 0.35f}, 1);
  EXPECT_GT(shadow_pt.r, 1.5f * shadow_d.r);
  EXPECT_EQ(reference_.non_finite(), 0u);
}

TEST(Pathtrace, DeterministicForASeedAndProgressive) {
  const std::string a = LoadCopy("cornell_box.gltf");
  const std::string b = LoadCopy("cornell_box.gltf");
  EncodedFrame fa, fb, fa2;
  Render(a, {{"spp", "2"}, {"seed", "7"}}, 16, {}, &fa);
  Render(b, {{"spp", "2"}, {"seed", "7"}}, 16, {}, &fb);
  EXPECT_EQ(fa.image, fb.image) << "same scene, seed and view must give the same image";
  // Same view again: samples accumulate.
  Render(a, {{"spp", "2"}, {"seed", "7"}}, 16, {}, &fa2);
  EXPECT_EQ(Stat(fa, "spp_total"), 2.0);
  EXPECT_EQ(Stat(fa2, "spp_total"), 4.0);
  EXPECT_NE(fa.image, fa2.image);
  // Any change restarts the accumulation.
  MaterialUpdate tint;
  tint.material = 0;
  tint.base_color = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  EncodedFrame restarted;
  Render(a, {{"spp", "2"}, {"seed", "7"}}, 16, {{1, tint}}, &restarted);
  EXPECT_EQ(Stat(restarted, "spp_total"), 2.0);
}

}  // namespace
}  // namespace gistream
