// The C++ reading of the GLSL BRDF albedo table (solvers/brdf_albedo.h)
// and the white-sky albedo built on it.
#include "solvers/brdf_albedo.h"

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "solvers/shading/ggx.h"
#include "solvers/shading/sampling.h"
#include "support/measurement.h"

namespace gistream {
namespace brdf_albedo_test {

// The table as the source file on disk spells it, read independently of
// the embedded copy and of BrdfAlbedoTable::Parse.
std::vector<glm::vec2> SourceTable() {
  std::ifstream in(std::string(GISTREAM_SOURCE_DIR "/shaders/common/brdf_albedo_table.glsl"));
  EXPECT_TRUE(in) << "shaders/common/brdf_albedo_table.glsl";
  std::stringstream text;
  text << in.rdbuf();
  const std::string body = text.str();
  const std::regex pair(R"(vec2\(([0-9.]+), ([0-9.]+)\))");
  std::vector<glm::vec2> table;
  for (auto it = std::sregex_iterator(body.begin(), body.end(), pair); it != std::sregex_iterator();
       ++it) {
    table.emplace_back(std::stof((*it)[1]), std::stof((*it)[2]));
  }
  return table;
}

// Every entry of the embedded table equals the GLSL source's (exactly: the
// same decimal text read as float), and the lookup returns the entries at
// the cell centres, their mean halfway between, and clamps outside.
TEST(BrdfAlbedo, EmbeddedTableEqualsTheGlslSource) {
  const BrdfAlbedoTable& table = BrdfAlbedoTable::Embedded();
  const std::vector<glm::vec2> source = SourceTable();
  ASSERT_EQ(table.size(), 16);
  ASSERT_EQ(source.size(), 256u);
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const glm::vec2 s = source[size_t(j * 16 + i)];
      EXPECT_EQ(table.at(i, j), s) << i << ", " << j;
      const glm::vec2 centre = table.Lookup((float(i) + 0.5f) / 16.0f, (float(j) + 0.5f) / 16.0f);
      EXPECT_NEAR(centre.x, s.x, 1e-6f) << i << ", " << j;
      EXPECT_NEAR(centre.y, s.y, 1e-6f) << i << ", " << j;
    }
  }
  const glm::vec2 half = table.Lookup(3.0f / 16.0f, 0.5f / 16.0f);  // between i = 2 and 3
  EXPECT_NEAR(half.x, 0.5f * (source[2].x + source[3].x), 1e-6f);
  EXPECT_NEAR(half.y, 0.5f * (source[2].y + source[3].y), 1e-6f);
  EXPECT_EQ(table.Lookup(0.0f, 0.0f), source[0]);
  EXPECT_EQ(table.Lookup(1.0f, 1.0f), source[255]);
}

TEST(BrdfAlbedo, ParseNamesTheBrokenPart) {
  EXPECT_NE(BrdfAlbedoTable::Parse("const vec2 x;").status().message().find("BRDF_TABLE_SIZE"),
            std::string_view::npos);
  const auto short_table = BrdfAlbedoTable::Parse(
      "const int BRDF_TABLE_SIZE = 2;\nconst vec2 BRDF_ALBEDO_TABLE[4] = vec2[](vec2(1, 0));");
  ASSERT_FALSE(short_table.ok());
  EXPECT_NE(short_table.status().message().find("1 entries"), std::string_view::npos)
      << short_table.status();
}

// Lambertian (metallic 0, roughness 1): the base colour, bitwise.
TEST(BrdfAlbedo, LambertianWhiteSkyIsTheBaseColourBitwise) {
  const glm::vec3 base(0.73f, 0.0123f, 0.999f);
  EXPECT_EQ(BrdfWhiteSkyAlbedo(base, 0.0f, 1.0f), base);
}

// Gold (metallic 1, roughness 0.3): no diffuse lobe; F0 (A - B) + B with the
// table's white-sky (A, B), and that agrees with the path tracer's BRDF
// (shading/ggx.h) sampled over cosine-weighted view directions:
// 2 int E(mu) mu dmu = E[f cos / pdf] for mu = sqrt(u). 400k samples, 4
// sigma < 0.003; the table itself is within 0.01 (Ggx.GlslAlbedoTable*).
TEST(BrdfAlbedo, GlossyWhiteSkyMatchesTheTableAndTheBrdf) {
  const BrdfAlbedoTable& table = BrdfAlbedoTable::Embedded();
  struct Case {
    glm::vec3 base;
    float metallic, roughness;
    glm::vec3 f0{0.04f};  // the dielectric layer (KHR_materials_ior / _specular)
    float f90 = 1.0f;
  };
  const Case cases[] = {{{1.0f, 0.78f, 0.34f}, 1.0f, 0.3f},  // glossy_box's gold
                        {{0.8f, 0.8f, 0.8f}, 0.0f, 0.5f},
                        {{0.5f, 0.2f, 0.9f}, 0.5f, 0.8f},
                        // A tinted, half-strength specular layer; a bright one.
                        {{0.6f, 0.3f, 0.3f}, 0.0f, 0.4f, {0.02f, 0.01f, 0.005f}, 0.5f},
                        {{0.2f, 0.2f, 0.2f}, 0.0f, 0.3f, {0.5f, 0.5f, 0.5f}, 1.0f}};
  for (const Case& c : cases) {
    const glm::vec3 albedo = BrdfWhiteSkyAlbedo(c.base, c.metallic, c.roughness, c.f0, c.f90);
    if (c.metallic == 1.0f) {
      const glm::vec2 ws = table.WhiteSky(c.roughness);
      const glm::vec3 expected = c.base * (ws.x - ws.y) + ws.y;
      for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(albedo[k], expected[k]) << k;
      testing::RecordMeasurement("gold_white_sky_A", ws.x);
      testing::RecordMeasurement("gold_white_sky_B", ws.y);
    }
    const shading::Brdf brdf{c.base, c.metallic, c.roughness, c.f0, c.f90};
    shading::Rng rng(5, 18);
    glm::dvec3 sum(0.0);
    const int n = 400000;
    for (int k = 0; k < n; ++k) {
      const double mu = std::sqrt(double(rng.Uniform())), phi = 6.283185307179586 * rng.Uniform();
      const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
      const glm::vec3 wo(float(s * std::cos(phi)), float(s * std::sin(phi)), float(mu));
      const glm::vec3 u(rng.Uniform(), rng.Uniform(), rng.Uniform());
      sum += glm::dvec3(shading::Sample(brdf, wo, u).weight);
    }
    const glm::dvec3 reference = sum / double(n);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(albedo[k], reference[k], 0.012)
          << "metallic " << c.metallic << " roughness " << c.roughness << " channel " << k;
      EXPECT_LE(albedo[k], 1.0f);
    }
  }
}

}  // namespace brdf_albedo_test
}  // namespace gistream
