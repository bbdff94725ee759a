// The reference path tracer against closed forms (white furnace, inverse
// square law, glTF spot falloff, an environment map's irradiance) and
// against `direct` on the Cornell box. Stochastic output is
// judged by means over many samples with tolerances several standard
// errors wide.
#include <cmath>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "scene/gltf/gltf_import.h"
#include "support/gltf_builder.h"
#include "support/render_helpers.h"

namespace gistream {
namespace pathtrace_test {

using testing::FloatImage;

constexpr float kPi = 3.14159265358979f;

using testing::BundledCopy;
using testing::FrameStage;

double Stat(const EncodedFrame& frame, const std::string& name) {
  return testing::FrameStat(frame, name);
}
glm::dvec3 Mean(const FloatImage& image) { return testing::ImageMean(image); }

// The view of a scene camera made by GltfBuilder::AddCamera looking down
// (-Y) with up = -Z.
ViewCamera LookingDown(const glm::vec3& position, float yfov, uint32_t size) {
  ViewCamera camera;
  camera.position = position;
  camera.rotation =
      glm::quat_cast(glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0)));
  camera.yfov = yfov;
  camera.width = camera.height = size;
  return camera;
}

// The point of the plane y = 0 seen through `offset` (0..1, default the
// centre) inside pixel px (x right, y down).
glm::vec3 PlanePoint(const ViewCamera& camera, glm::ivec2 px, glm::vec2 offset = {0.5f, 0.5f}) {
  const glm::mat4 inv = glm::inverse(camera.Projection() * camera.View());
  const glm::vec2 ndc((float(px.x) + offset.x) / float(camera.width) * 2.0f - 1.0f,
                      1.0f - (float(px.y) + offset.y) / float(camera.height) * 2.0f);
  const glm::vec4 far = inv * glm::vec4(ndc, 0.5f, 1.0f);
  const glm::vec3 dir = glm::normalize(glm::vec3(far) / far.w - camera.position);
  return camera.position + dir * (camera.position.y / -dir.y);
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

TEST(Pathtrace, EmissionChangeKeepsTheBvh) {
  // Doubling the emission doubles L (4 at rho = 0.5): the emitter table is
  // rebuilt, the BVH is not (build_bvh reported skipped).
  const BundledCopy scene("furnace.gltf");
  const std::string& id = scene.id();
  EncodedFrame first, changed;
  // Same parameters both times: they select the (shared) solver instance.
  Render(id, {{"spp", "64"}}, 16, {}, &first);
  const StageTiming* build = FrameStage(first, "build_bvh");
  ASSERT_NE(build, nullptr);
  EXPECT_FALSE(build->skipped);
  EXPECT_TRUE(build->cpu_stage);
  MaterialUpdate brighter;
  brighter.material = 0;
  brighter.emissive_strength = 2.0f;
  const FloatImage image = Render(id, {{"spp", "64"}}, 16, {{1, brighter}}, &changed);
  ASSERT_EQ(image.width, 16);
  build = FrameStage(changed, "build_bvh");
  ASSERT_NE(build, nullptr);
  EXPECT_TRUE(build->skipped);
  const StageTiming* trace = FrameStage(changed, "trace");
  ASSERT_NE(trace, nullptr);
  EXPECT_TRUE(trace->cpu_stage);
  EXPECT_FALSE(FrameStage(changed, "accumulate")->skipped);
  EXPECT_EQ(Stat(changed, "spp_total"), 64.0);
  // As in WhiteFurnaceHalfAlbedo, twice the value: 1 % is over two
  // standard errors.
  EXPECT_NEAR(Mean(image).g, 4.0, 0.04);
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
  const ViewCamera camera = LookingDown({0.0f, 1.0f, 0.0f}, 1.2f, 32);
  const glm::mat4 inv = glm::inverse(camera.Projection() * camera.View());
  for (const glm::ivec2 px :
       {glm::ivec2(16, 16), glm::ivec2(3, 16), glm::ivec2(28, 4), glm::ivec2(6, 27)}) {
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

TEST(Pathtrace, SpotLightOverPlane) {
  // A spot light pointing down: full intensity inside the inner cone, the
  // glTF smooth falloff between the cones, nothing outside the outer one.
  const float albedo = 0.7f, intensity = 20.0f, height = 1.0f;
  const float inner = 0.3f, outer = 0.6f;
  testing::GltfBuilder b;
  const int mat = b.AddMaterial("plane", {albedo, albedo, albedo});
  b.AddQuad("plane", {0, 0, 0}, {0, 0, 20}, {20, 0, 0}, mat);
  b.AddSpotLightDown("spot", {0.0f, height, 0.0f}, {1, 1, 1}, intensity, inner, outer);
  b.AddCamera("camera", {0.0f, 2.0f, 0.0f}, {0, -1, 0}, {0, 0, -1}, 1.4f);
  auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(b.ToJson()));
  ASSERT_TRUE(info.ok()) << info.status();
  // The pixel jitter is the only noise (no indirect light), but between the
  // cones the radiance changes by up to +-60 % across a pixel: 4096 spp.
  const FloatImage image = Render(info->id, {{"spp", "4096"}}, 32);
  ASSERT_EQ(image.width, 32);
  const ViewCamera camera = LookingDown({0.0f, 2.0f, 0.0f}, 1.4f, 32);
  const float scale = 1.0f / std::max(0.001f, std::cos(inner) - std::cos(outer));
  auto radiance = [&](const glm::vec3& p) {
    const float r2 = glm::dot(p, p) + height * height, cos_t = height / std::sqrt(r2);
    float att = std::clamp(cos_t * scale - std::cos(outer) * scale, 0.0f, 1.0f);
    att *= att;
    return albedo / kPi * intensity * att * cos_t / r2;
  };
  for (const float radius : {0.1f, 0.45f, 0.55f, 1.0f}) {
    const glm::ivec2 px = testing::Project(camera, glm::vec3(radius, 0.0f, 0.0f));
    // The exact pixel mean: the closed form averaged over a 16x16 grid of
    // points in the pixel (the tracer jitters uniformly over it).
    double expected = 0.0;
    for (int j = 0; j < 16; ++j) {
      for (int i = 0; i < 16; ++i) {
        expected += radiance(PlanePoint(camera, px, {(i + 0.5f) / 16.0f, (j + 0.5f) / 16.0f}));
      }
    }
    expected /= 256.0;
    // 4096 jittered samples of a value whose standard deviation over the
    // pixel is up to 0.6 of its mean: standard error about 1 % (measured:
    // +1.0 % at 0.55 m, +0.6 % at 0.65 m); 4 % is four of them. Outside
    // the outer cone: exactly 0.
    EXPECT_NEAR(image.at(px.x, px.y).g, expected, 0.04 * expected + 1e-6) << radius;
  }
}

// An equirectangular map, rows top (zenith) first: `sky` above the
// horizon, `ground` below it, and one bright `sun` texel.
struct EnvMap {
  static constexpr int kWidth = 32, kHeight = 16;
  glm::vec3 sky{0.8f, 1.0f, 1.2f}, ground{0.3f, 0.3f, 0.3f}, sun{400.0f, 300.0f, 200.0f};
  glm::ivec2 sun_texel{5, 3};
  glm::vec3 at(int x, int y) const {
    if (glm::ivec2(x, y) == sun_texel) return sun;
    return y < kHeight / 2 ? sky : ground;
  }
  std::string Exr() const {
    return testing::EnvironmentExr(kWidth, kHeight, [this](int x, int y) { return at(x, y); });
  }
  // Irradiance on an upward-facing surface: each texel is a constant
  // patch, so E = sum L * dphi * (sin^2 theta1 - sin^2 theta0) / 2 over the
  // upper hemisphere (the horizon lies on a row boundary).
  glm::dvec3 IrradianceUp() const {
    glm::dvec3 e(0.0);
    const double dphi = 2.0 * kPi / kWidth;
    for (int y = 0; y < kHeight / 2; ++y) {
      const double s0 = std::sin(kPi * y / kHeight), s1 = std::sin(kPi * (y + 1) / kHeight);
      for (int x = 0; x < kWidth; ++x) e += glm::dvec3(at(x, y)) * dphi * (s1 * s1 - s0 * s0) / 2.0;
    }
    return e;
  }
};

TEST(Pathtrace, EnvironmentOverPlane) {
  // A diffuse plane under an environment with a small, 100x brighter sun:
  // L = rho / pi * intensity * E, E summed exactly over the texels (the sun
  // gives about two thirds of it). With the map importance-sampled a
  // path's standard deviation is about 0.6 of the mean (measured), so the
  // mean of 16k paths has a standard error of 0.5 %; 2 % is four of them
  // (measured: within 0.2 % in every channel).
  const float albedo = 0.5f, intensity = 1.5f;
  testing::GltfBuilder b;
  const int mat = b.AddMaterial("plane", {albedo, albedo, albedo});
  b.AddQuad("plane", {0, 0, 0}, {0, 0, 100}, {100, 0, 0}, mat);
  b.AddCamera("camera", {0.0f, 1.0f, 0.0f}, {0, -1, 0}, {0, 0, -1}, 1.0f);
  const EnvMap env;
  SceneSource source = testing::SceneFromBytes(b.ToJson());
  source.environment_bytes = env.Exr();
  source.environment_intensity = intensity;
  auto info = testing::SharedEngine().LoadScene(source);
  ASSERT_TRUE(info.ok()) << info.status();
  EncodedFrame frame;
  const FloatImage image = Render(info->id, {{"spp", "64"}}, 16, {}, &frame);
  ASSERT_EQ(image.width, 16);
  EXPECT_EQ(image.non_finite(), 0u);
  const glm::dvec3 expected = double(albedo / kPi * intensity) * env.IrradianceUp();
  const glm::dvec3 mean = Mean(image);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], expected[c], 0.02 * expected[c]) << c;
  EXPECT_EQ(Stat(frame, "nonfinite_samples"), 0.0);
}

TEST(Pathtrace, EnvironmentSeenDirectly) {
  // Camera rays that escape show the map times its intensity, exactly. The
  // camera looks at the horizon along -Z (u = 0) with a narrow field of
  // view, so every pixel lands in sky row 7 or ground row 8.
  testing::GltfBuilder b;
  const int mat = b.AddMaterial("behind", {0.5f, 0.5f, 0.5f});
  b.AddQuad("behind", {0, 0, 10}, {1, 0, 0}, {0, 1, 0}, mat);  // behind the camera
  b.AddCamera("camera", {0.0f, 0.0f, 0.0f}, {0, 0, -1}, {0, 1, 0}, 0.1f);
  EnvMap env;
  env.sun_texel = {-1, -1};
  SceneSource source = testing::SceneFromBytes(b.ToJson());
  source.environment_bytes = env.Exr();
  source.environment_intensity = 2.0f;
  auto info = testing::SharedEngine().LoadScene(source);
  ASSERT_TRUE(info.ok()) << info.status();
  const FloatImage image = Render(info->id, {{"spp", "1"}}, 8);
  ASSERT_EQ(image.width, 8);
  EXPECT_NEAR(image.at(4, 1).b, 2.0f * env.sky.b, 1e-5f);     // top rows: above the horizon
  EXPECT_NEAR(image.at(4, 6).b, 2.0f * env.ground.b, 1e-5f);  // bottom rows: below it
}

class PathtraceCornell : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const BundledCopy copy("cornell_box.gltf");
    const std::string& id = copy.id();
    auto scene = ImportSceneByName(std::string(GISTREAM_SOURCE_DIR "/scenes"), "cornell_box", {});
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

TEST(Pathtrace, TimeBudgetTracesUntilSpent) {
  // 1-spp rounds until the budget is spent: at least one, and the trace
  // time reaches the budget.
  const BundledCopy scene("furnace.gltf");
  const std::string& id = scene.id();
  EncodedFrame frame;
  Render(id, {{"time_budget_ms", "40"}}, 8, {}, &frame);
  EXPECT_GE(Stat(frame, "spp_frame"), 1.0);
  EXPECT_GE(Stat(frame, "trace_ms"), 40.0);
  EXPECT_EQ(Stat(frame, "spp_total"), Stat(frame, "spp_frame"));
  EXPECT_GT(Stat(frame, "rays"), 0.0);
}

TEST(Pathtrace, DeterministicForASeedAndProgressive) {
  const BundledCopy copy_a("cornell_box.gltf"), copy_b("cornell_box.gltf");
  const std::string &a = copy_a.id(), &b = copy_b.id();
  EncodedFrame fa, fb, fa2;
  Render(a, {{"spp", "2"}, {"seed", "7"}}, 16, {}, &fa);
  Render(b, {{"spp", "2"}, {"seed", "7"}}, 16, {}, &fb);
  // Pixels, not EXR bytes: the header carries the time of writing.
  EXPECT_EQ(testing::DecodeExr(fa).rgba, testing::DecodeExr(fb).rgba)
      << "same scene, seed and view must give the same image";
  // Same view again: samples accumulate.
  Render(a, {{"spp", "2"}, {"seed", "7"}}, 16, {}, &fa2);
  EXPECT_EQ(Stat(fa, "spp_total"), 2.0);
  EXPECT_EQ(Stat(fa2, "spp_total"), 4.0);
  EXPECT_NE(testing::DecodeExr(fa).rgba, testing::DecodeExr(fa2).rgba);
  // Any change restarts the accumulation.
  MaterialUpdate tint;
  tint.material = 0;
  tint.base_color = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  EncodedFrame restarted;
  Render(a, {{"spp", "2"}, {"seed", "7"}}, 16, {{1, tint}}, &restarted);
  EXPECT_EQ(Stat(restarted, "spp_total"), 2.0);
}

}  // namespace pathtrace_test
}  // namespace gistream
