// Glossy surfaces (glTF metallic-roughness, GGX) lit directly, in `direct`
// (shaders/common/brdf.glsl) and `pathtrace` (solvers/shading/ggx.h),
// against the closed form: a point light over a glossy plane and nothing
// else, so the plane sends L = f(v, l) I cos(theta) / r^2 to the eye, with
// f from ggx.h evaluated here. Two cases set the dielectric layer's
// Fresnel through KHR_materials_ior / KHR_materials_specular (issue 29):
// the G-buffer carries each material's F0 and F90 to the GLSL BRDF.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "solvers/shading/ggx.h"
#include "support/gltf_builder.h"
#include "support/render_helpers.h"

namespace gistream {
namespace glossy_direct_test {

using testing::GltfBuilder;

constexpr uint32_t kSize = 64;
constexpr float kHeight = 0.8f;  // the camera's, looking straight down
const glm::vec3 kLight(0.35f, 1.0f, 0.2f);
constexpr float kIntensity = 10.0f;

struct GlossyCase {
  const char* name;
  glm::vec3 base_color;
  float metallic;
  float roughness;
  // KHR_materials_ior's ior and KHR_materials_specular's factors; the
  // dielectric F0 and F90 they make (gltf_extensions.cpp).
  float ior = 1.5f;
  glm::vec3 specular_color{1.0f};
  float specular_factor = 1.0f;
  bool extensions = false;
  glm::vec3 f0() const {
    const float r = (ior - 1.0f) / (ior + 1.0f);
    return glm::min(r * r * specular_color, glm::vec3(1.0f)) * specular_factor;
  }
};
// ctest's test names show the case, not its bytes.
void PrintTo(const GlossyCase& c, std::ostream* os) { *os << c.name; }

ViewCamera Camera() {
  ViewCamera camera;
  camera.position = {0.0f, kHeight, 0.0f};
  camera.rotation =
      glm::quat_cast(glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0)));
  camera.yfov = 1.6f;
  camera.width = camera.height = kSize;
  return camera;
}

// The point of the plane y = 0 seen through `offset` (0..1) inside pixel px.
glm::vec3 PlanePoint(const ViewCamera& camera, glm::ivec2 px, glm::vec2 offset) {
  const glm::mat4 inv = glm::inverse(camera.Projection() * camera.View());
  const glm::vec2 ndc((float(px.x) + offset.x) / float(camera.width) * 2.0f - 1.0f,
                      1.0f - (float(px.y) + offset.y) / float(camera.height) * 2.0f);
  const glm::vec4 far = inv * glm::vec4(ndc, 0.5f, 1.0f);
  const glm::vec3 dir = glm::normalize(glm::vec3(far) / far.w - camera.position);
  return camera.position + dir * (camera.position.y / -dir.y);
}

// L = f(v, l) I cos / r^2 at plane point p (normal +Y: the local frame's z).
glm::vec3 Expected(const GlossyCase& c, const glm::vec3& p, const glm::vec3& eye) {
  const glm::vec3 d = kLight - p;
  const float r2 = glm::dot(d, d);
  const glm::vec3 l = d / std::sqrt(r2), v = glm::normalize(eye - p);
  // World (x, y, z) -> local (x, z, y): y is the normal; handedness does
  // not matter to an isotropic BRDF.
  const glm::vec3 wo(v.x, v.z, v.y), wi(l.x, l.z, l.y);
  const shading::Brdf brdf{c.base_color, c.metallic, c.roughness, c.f0(), c.specular_factor};
  return shading::Eval(brdf, wo, wi) * (kIntensity * wi.z / r2);
}

class GlossyDirect : public ::testing::TestWithParam<GlossyCase> {
 protected:
  std::string Load() {
    const GlossyCase& c = GetParam();
    GltfBuilder b;
    const int mat = b.AddMaterial("plane", {c.base_color.r, c.base_color.g, c.base_color.b});
    b.SetMetallicRoughness(mat, c.metallic, c.roughness);
    if (c.extensions) {
      b.SetMaterialExtension(mat, "KHR_materials_ior", {{"ior", c.ior}});
      b.SetMaterialExtension(
          mat, "KHR_materials_specular",
          {{"specularFactor", c.specular_factor},
           {"specularColorFactor", {c.specular_color.r, c.specular_color.g, c.specular_color.b}}});
    }
    b.AddQuad("plane", {0, 0, 0}, {0, 0, 4}, {4, 0, 0}, mat, 4);
    b.AddPointLight("lamp", {kLight.x, kLight.y, kLight.z}, {1, 1, 1}, kIntensity);
    b.AddCamera("camera", {0.0f, kHeight, 0.0f}, {0, -1, 0}, {0, 0, -1}, 1.6f);
    // Unloaded with the test (the engine holds at most --max-scenes).
    scene_ = std::make_unique<testing::TestScene>(testing::SceneFromBytes(b.ToJson()));
    return scene_->id();
  }
  std::unique_ptr<testing::TestScene> scene_;
  static constexpr glm::ivec2 kPixels[] = {{32, 32}, {38, 29}, {44, 26}, {10, 32},
                                           {50, 12}, {5, 58},  {40, 45}};

  // The closed form at pixel centres (the G-buffer's sample points), 1 %.
  void ExpectBrdfAtPixelCentres(const testing::FloatImage& image) const {
    ASSERT_EQ(image.width, int(kSize));
    const ViewCamera camera = Camera();
    for (const glm::ivec2 px : kPixels) {
      const glm::vec3 expected =
          Expected(GetParam(), PlanePoint(camera, px, {0.5f, 0.5f}), camera.position);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(image.at(px.x, px.y)[k], expected[k], 0.01f * expected[k] + 1e-6f)
            << "pixel " << px.x << "," << px.y << " channel " << k;
      }
    }
  }
};

// The GLSL BRDF at pixel centres (the G-buffer's sample points) equals the
// C++ one to float rounding: 1 % tolerance. The G-buffer keeps albedo and
// metallic in 8 bits, so the cases use multiples of 1/255 (0.2, 0.4, 0.6,
// 0.8, 1), which it stores exactly.
TEST_P(GlossyDirect, DirectSolverMatchesTheBrdf) {
  const std::string id = Load();
  ASSERT_FALSE(id.empty());
  ExpectBrdfAtPixelCentres(testing::RenderExr(testing::SharedEngine(), id, "direct", kSize, kSize));
}

// `avg` shades direct light through the same BRDF (its illuminate pass
// demodulates the glossy radiance by the directional albedo and its filter
// multiplies it back, avg/receiver.glsl). A lone plane gets no indirect
// light from its own VPLs: each sits above the plane, so cos_v < 0 towards
// every point of it and the gather skips it. The image is the closed form.
TEST_P(GlossyDirect, AvgMatchesTheBrdf) {
  const std::string id = Load();
  ASSERT_FALSE(id.empty());
  ExpectBrdfAtPixelCentres(testing::RenderExr(testing::SharedEngine(), id, "avg", kSize, kSize,
                                              {{"vpls", "64"}, {"shadow_res", "16"}}));
}

// The path tracer averages over each pixel (64 jittered samples; the point
// light is sampled exactly at each): against the mean of the closed form
// over an 8 x 8 grid in the pixel, within 3 % (the jitter's sampling error
// where the lobe changes fastest across a pixel).
TEST_P(GlossyDirect, PathtraceMatchesTheBrdf) {
  const std::string id = Load();
  ASSERT_FALSE(id.empty());
  const testing::FloatImage image =
      testing::RenderExr(testing::SharedEngine(), id, "pathtrace", kSize, kSize, {{"spp", "64"}});
  ASSERT_EQ(image.width, int(kSize));
  const ViewCamera camera = Camera();
  for (const glm::ivec2 px : kPixels) {
    glm::vec3 expected(0.0f);
    for (int i = 0; i < 8; ++i) {
      for (int j = 0; j < 8; ++j) {
        const glm::vec2 offset((float(i) + 0.5f) / 8.0f, (float(j) + 0.5f) / 8.0f);
        expected += Expected(GetParam(), PlanePoint(camera, px, offset), camera.position) / 64.0f;
      }
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(image.at(px.x, px.y)[k], expected[k], 0.03f * expected[k] + 1e-6f)
          << "pixel " << px.x << "," << px.y << " channel " << k;
    }
  }
}

// A material update makes a Lambertian plane glossy: `direct` then shows
// the BRDF of the new metallic and roughness (the case's), as in
// DirectSolverMatchesTheBrdf. (The plane is loaded without the case's
// extensions: its dielectric layer is the default one.)
TEST_P(GlossyDirect, MaterialUpdateSetsMetallicAndRoughness) {
  GlossyCase c = GetParam();
  c.ior = 1.5f;
  c.specular_color = glm::vec3(1.0f);
  c.specular_factor = 1.0f;
  GltfBuilder b;
  const int mat = b.AddMaterial("plane", {c.base_color.r, c.base_color.g, c.base_color.b});
  b.AddQuad("plane", {0, 0, 0}, {0, 0, 4}, {4, 0, 0}, mat, 4);
  b.AddPointLight("lamp", {kLight.x, kLight.y, kLight.z}, {1, 1, 1}, kIntensity);
  b.AddCamera("camera", {0.0f, kHeight, 0.0f}, {0, -1, 0}, {0, 0, -1}, 1.6f);
  const testing::TestScene scene(testing::SceneFromBytes(b.ToJson()));
  ASSERT_FALSE(scene.id().empty());
  MaterialUpdate update;
  update.material = uint32_t(mat);
  update.metallic = c.metallic;
  update.roughness = c.roughness;
  RenderRequest request;
  request.scene = scene.id();
  request.solver = "direct";
  request.width = request.height = kSize;
  request.updates = {Update{1, update}};
  request.refine_samples = 1;  // the BRDF at pixel centres
  const testing::FloatImage image = testing::RenderRequestExr(request);
  ASSERT_EQ(image.width, int(kSize));
  const ViewCamera camera = Camera();
  for (const glm::ivec2 px : kPixels) {
    const glm::vec3 expected = Expected(c, PlanePoint(camera, px, {0.5f, 0.5f}), camera.position);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(image.at(px.x, px.y)[k], expected[k], 0.01f * expected[k] + 1e-6f)
          << "pixel " << px.x << "," << px.y << " channel " << k;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Materials, GlossyDirect,
    ::testing::Values(
        GlossyCase{"gold_metal", {1.0f, 0.8f, 0.4f}, 1.0f, 0.4f},
        GlossyCase{"red_plastic", {0.8f, 0.2f, 0.2f}, 0.0f, 0.3f},
        GlossyCase{"rough_dielectric", {0.6f, 0.6f, 0.6f}, 0.0f, 0.8f},
        // Water's ior (F0 0.020), and a tinted, weaker
        // specular layer (F0 0.04 x (1, 0.5, 0.2) x 0.6, F90 0.6).
        GlossyCase{"water_ior", {0.2f, 0.2f, 0.2f}, 0.0f, 0.3f, 1.33f, glm::vec3(1.0f), 1.0f, true},
        GlossyCase{"tinted_specular",
                   {0.4f, 0.4f, 0.4f},
                   0.0f,
                   0.3f,
                   1.5f,
                   glm::vec3(1.0f, 0.5f, 0.2f),
                   0.6f,
                   true}),
    [](const ::testing::TestParamInfo<GlossyCase>& p) { return p.param.name; });

}  // namespace glossy_direct_test
}  // namespace gistream
