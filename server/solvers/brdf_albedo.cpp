#include "solvers/brdf_albedo.h"

#include <charconv>
#include <string>

#include <absl/strings/str_cat.h>

#include "gl/shader_library.h"

namespace gistream {
namespace {

constexpr std::string_view kTablePath = "common/brdf_albedo_table.glsl";

// The float starting at text[pos] (after spaces); advances pos past it.
bool ReadFloat(std::string_view text, size_t& pos, float& value) {
  while (pos < text.size() && text[pos] == ' ') ++pos;
  const auto [end, ec] = std::from_chars(text.data() + pos, text.data() + text.size(), value);
  if (ec != std::errc()) return false;
  pos = size_t(end - text.data());
  return true;
}

}  // namespace

absl::StatusOr<BrdfAlbedoTable> BrdfAlbedoTable::Parse(std::string_view glsl) {
  BrdfAlbedoTable table;
  constexpr std::string_view kSize = "BRDF_TABLE_SIZE = ";
  size_t pos = glsl.find(kSize);
  if (pos == std::string_view::npos) return absl::InvalidArgumentError("BRDF_TABLE_SIZE missing");
  pos += kSize.size();
  const auto [end, ec] = std::from_chars(glsl.data() + pos, glsl.data() + glsl.size(), table.size_);
  if (ec != std::errc() || table.size_ < 2 || table.size_ > 256) {
    return absl::InvalidArgumentError("BRDF_TABLE_SIZE: not an integer in [2, 256]");
  }
  pos = glsl.find("BRDF_ALBEDO_TABLE[", size_t(end - glsl.data()));
  if (pos == std::string_view::npos) return absl::InvalidArgumentError("BRDF_ALBEDO_TABLE missing");
  constexpr std::string_view kEntry = "vec2(";
  while ((pos = glsl.find(kEntry, pos)) != std::string_view::npos) {
    pos += kEntry.size();
    glm::vec2 e;
    bool ok = ReadFloat(glsl, pos, e.x) && pos < glsl.size() && glsl[pos] == ',';
    ok = ok && ReadFloat(glsl, ++pos, e.y) && pos < glsl.size() && glsl[pos] == ')';
    if (!ok) {
      return absl::InvalidArgumentError(
          absl::StrCat("BRDF_ALBEDO_TABLE[", table.entries_.size(), "]: not vec2(float, float)"));
    }
    table.entries_.push_back(e);
  }
  if (table.entries_.size() != size_t(table.size_ * table.size_)) {
    return absl::InvalidArgumentError(
        absl::StrCat("BRDF_ALBEDO_TABLE: ", table.entries_.size(),
                     " entries, BRDF_TABLE_SIZE^2 = ", table.size_ * table.size_));
  }
  return table;
}

const BrdfAlbedoTable& BrdfAlbedoTable::Embedded() {
  static const BrdfAlbedoTable table = [] {
    absl::StatusOr<std::string_view> text = gl::EmbeddedShaderSource(kTablePath);
    GS_CHECK(text.ok());
    absl::StatusOr<BrdfAlbedoTable> parsed = Parse(*text);
    GS_CHECK(parsed.ok());
    return *std::move(parsed);
  }();
  return table;
}

glm::vec2 BrdfAlbedoTable::Lookup(float nv, float roughness) const {
  // As brdf.glsl's BrdfAlbedoTable, operation for operation.
  const float n = float(size_);
  const glm::vec2 x =
      glm::clamp(glm::vec2(nv, roughness) * n - 0.5f, glm::vec2(0.0f), glm::vec2(n - 1.0f));
  const glm::ivec2 i0(glm::floor(x));
  const glm::ivec2 i1 = glm::min(i0 + 1, glm::ivec2(size_ - 1));
  const glm::vec2 t = x - glm::vec2(i0);
  const glm::vec2 a = glm::mix(at(i0.x, i0.y), at(i1.x, i0.y), t.x);
  const glm::vec2 b = glm::mix(at(i0.x, i1.y), at(i1.x, i1.y), t.x);
  return glm::mix(a, b, t.y);
}

glm::vec2 BrdfAlbedoTable::WhiteSky(float roughness) const {
  // 2 int_0^1 E(mu) mu dmu; Lookup is piecewise linear in mu with kinks at
  // the cell centres, so 64 midpoint steps per cell are exact to ~1e-5.
  const int steps = 64 * size_;
  glm::dvec2 sum(0.0);
  for (int k = 0; k < steps; ++k) {
    const float mu = (float(k) + 0.5f) / float(steps);
    sum += glm::dvec2(Lookup(mu, roughness)) * double(mu);
  }
  return glm::vec2(2.0 * sum / double(steps));
}

glm::vec3 BrdfWhiteSkyAlbedo(const glm::vec3& base_color, float metallic, float roughness,
                             const glm::vec3& specular_f0, float specular_f90) {
  if (metallic == 0.0f && roughness == 1.0f) return base_color;  // BrdfLambertian
  const glm::vec3 f0 = glm::mix(specular_f0, base_color, metallic);
  const glm::vec3 f90(specular_f90 + (1.0f - specular_f90) * metallic);
  // BrdfUniformAlbedo's diffuse lobe (1 - F(n.v)) (1 - F_avg), averaged
  // over n.v with weight 2 n.v: (1 - F_avg)^2, F_avg = F0 + (F90 - F0) / 21
  // (2 int_0^1 (1 - mu)^5 mu dmu = 1/21).
  const glm::vec3 f_avg = f0 + (f90 - f0) / 21.0f;
  const glm::vec3 diffuse = (1.0f - metallic) * base_color * (1.0f - f_avg) * (1.0f - f_avg);
  // Specular: E = F0 (A - B) + F90 B is linear in (A, B), so its white-sky
  // mean is F0 (A_ws - B_ws) + F90 B_ws.
  const glm::vec2 ab = BrdfAlbedoTable::Embedded().WhiteSky(roughness);
  return diffuse + f0 * (ab.x - ab.y) + f90 * ab.y;
}

glm::vec3 BrdfDirectionalAlbedo(const glm::vec3& base_color, float metallic, float roughness,
                                float nv, const glm::vec3& specular_f0, float specular_f90) {
  if (metallic == 0.0f && roughness == 1.0f) return base_color;  // BrdfLambertian
  // As brdf.glsl's BrdfUniformAlbedo, operation for operation.
  const float mu = glm::clamp(nv, 0.0f, 1.0f);
  const glm::vec3 f0 = glm::mix(specular_f0, base_color, metallic);
  const glm::vec3 f90(specular_f90 + (1.0f - specular_f90) * metallic);
  const float m = 1.0f - mu, m5 = m * m * m * m * m;
  const glm::vec3 diffuse = (1.0f - metallic) * base_color * (1.0f - (f0 + (f90 - f0) * m5)) *
                            (1.0f - (f0 + (f90 - f0) / 21.0f));
  const glm::vec2 ab = BrdfAlbedoTable::Embedded().Lookup(mu, roughness);
  return diffuse + f0 * (ab.x - ab.y) + f90 * ab.y;
}

}  // namespace gistream
