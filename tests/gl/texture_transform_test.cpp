// KHR_texture_transform (issue 29: files nobody here wrote): each texture
// reference's offset, rotation and scale move its coordinates, uv' = T R S
// (uv, 1), in every solver (shaders/common/material.glsl, pathtrace's
// texture lookups). Until 2026-12-05 it was type-checked and reported as
// ignored. Closed form: a quad filling the view, black, with an emissive
// texture of 8 x 1 texels (left half red, right half green), so every
// solver shows the texture itself: red on the left and green on the right,
// swapped by an offset of (0.5, 0) (the texture wraps), and with a scale of
// (2, 1) red, green, red, green across the four quarters. The texture's
// glTF sampler (glTF 2.0 5.26) wraps the coordinates outside [0, 1] and
// filters between texels: under scale (2, 1) the right half reads u' in
// [1, 2], which repeat, clamp to edge and mirrored repeat map to red-green,
// green and green-red; at the texture's red-green edge, in the middle of
// the view, NEAREST gives pure colours where LINEAR blends them.
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "encode/encode.h"
#include "support/gltf_builder.h"
#include "support/registered_solvers.h"
#include "support/render_helpers.h"

namespace gistream {
namespace texture_transform_test {

constexpr uint32_t kSize = 32;

std::string RedGreenPng() {
  std::vector<uint8_t> rgba;
  for (int x = 0; x < 8; ++x) {
    rgba.insert(rgba.end(), {uint8_t(x < 4 ? 255 : 0), uint8_t(x < 4 ? 0 : 255), 0, 255});
  }
  auto png = EncodePng(rgba, 8, 1);
  EXPECT_TRUE(png.ok()) << png.status();
  return png.ok() ? *png : std::string();
}

// The quad from x = -1 to 1 (u 0 to 1) seen head-on, filling the view.
std::string QuadScene(const nlohmann::json& transform, const nlohmann::json& sampler) {
  testing::GltfBuilder b;
  b.EnableUvs();
  const int mat = b.AddMaterial("screen", {0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f});
  nlohmann::json info = {{"index", b.AddTexture(RedGreenPng(), sampler)}};
  if (!transform.is_null()) info["extensions"]["KHR_texture_transform"] = transform;
  b.SetTexture(mat, "emissiveTexture", info);
  b.AddQuad("screen", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, mat);
  b.AddCamera("camera", {0, 0, 2}, {0, 0, -1}, {0, 1, 0}, 0.9f);
  return b.ToJson();
}

class TextureTransform : public ::testing::TestWithParam<std::string> {
 protected:
  // The colour at the centres of the four vertical quarters of the view
  // (x = -0.73, -0.24, 0.24, 0.73 on the quad): 'r' or 'g' each.
  std::string Quarters(const nlohmann::json& transform, const nlohmann::json& sampler = nullptr) {
    return Columns(transform, sampler, {1, 3, 5, 7}, 8);
  }
  // 'r', 'g' or '?' (neither pure) at the middle row of each column
  // (kSize * c / d) of the view.
  std::string Columns(const nlohmann::json& transform, const nlohmann::json& sampler,
                      std::vector<int> columns, int d) {
    const testing::TestScene scene(testing::SceneFromBytes(QuadScene(transform, sampler)));
    EXPECT_FALSE(scene.id().empty());
    // The texture reaches the view through the G-buffer (pathtrace: its
    // own lookups), whatever the GI: sh_probes' smallest grid and one
    // bounce keep its renders from costing 1 s each.
    const std::map<std::string, std::string> params =
        GetParam() == "sh_probes"
            ? std::map<std::string, std::string>{{"grid", "2"}, {"bounces", "1"}}
            : std::map<std::string, std::string>{};
    const testing::FloatImage image =
        testing::RenderRequestExr(testing::SolverRequest(scene.id(), GetParam(), params, kSize));
    std::string out;
    for (int c : columns) {
      const glm::vec3 px = image.at(int(kSize) * c / d, int(kSize) / 2);
      const bool red = px.r > 0.95f && px.g<0.05f, green = px.g> 0.95f && px.r < 0.05f;
      out += red ? 'r' : green ? 'g' : '?';
    }
    return out;
  }
};

TEST_P(TextureTransform, OffsetAndScaleMoveTheTexture) {
  EXPECT_EQ(Quarters(nullptr), "rrgg");
  EXPECT_EQ(Quarters({{"offset", {0.5, 0.0}}}), "ggrr");
  EXPECT_EQ(Quarters({{"scale", {2.0, 1.0}}}), "rgrg");
}

TEST_P(TextureTransform, TheSamplerWrapsOutsideTheUnitSquare) {
  const nlohmann::json scale = {{"scale", {2.0, 1.0}}};
  EXPECT_EQ(Quarters(scale, {{"wrapS", 10497}}), "rgrg");  // REPEAT
  EXPECT_EQ(Quarters(scale, {{"wrapS", 33071}}), "rggg");  // CLAMP_TO_EDGE
  EXPECT_EQ(Quarters(scale, {{"wrapS", 33648}}), "rggr");  // MIRRORED_REPEAT
}

// Columns 15 and 16 of 32 see u = 0.485 and 0.515: texel coordinates 3.88
// and 4.12 of 8, either side of the red-green edge at 4 (bilinear: 62 %
// of the nearer texel's colour).
TEST_P(TextureTransform, TheSamplerFiltersBetweenTexels) {
  EXPECT_EQ(Columns(nullptr, {{"magFilter", 9728}}, {15, 16}, 32), "rg");  // NEAREST
  EXPECT_EQ(Columns(nullptr, {{"magFilter", 9729}}, {15, 16}, 32), "??");  // LINEAR
  EXPECT_EQ(Columns(nullptr, nullptr, {15, 16}, 32), "??");                // default: linear
}

INSTANTIATE_TEST_SUITE_P(EverySolver, TextureTransform,
                         ::testing::ValuesIn(testing::RegisteredSolverNames()),
                         [](const auto& p) { return p.param; });

}  // namespace texture_transform_test
}  // namespace gistream
