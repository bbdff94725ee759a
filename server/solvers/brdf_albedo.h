// The GGX specular lobe's uniform-light albedo table of
// shaders/common/brdf_albedo_table.glsl (written by tools/make_brdf_table.py),
// read in C++ from the same embedded shader text (no second copy), and the
// white-sky albedo of a glTF metallic-roughness surface built on it: what
// the surface reflects of light arriving from all directions alike,
// averaged over all viewing directions (cosine-weighted). Used where a
// surface's reflectance is one colour, e.g. avg's voxels (VPL flux).
#pragma once

#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "util/status.h"

namespace gistream {

class BrdfAlbedoTable {
 public:
  // Parses the GLSL file's BRDF_TABLE_SIZE and BRDF_ALBEDO_TABLE.
  static absl::StatusOr<BrdfAlbedoTable> Parse(std::string_view glsl);
  // The table embedded in the binary (parsed once; aborts if the embedded
  // file is missing or malformed, a build error that tests catch).
  static const BrdfAlbedoTable& Embedded();

  int size() const { return size_; }
  // Entry (A, B) at n.v = (i + 0.5) / size, roughness = (j + 0.5) / size.
  glm::vec2 at(int i, int j) const { return entries_[size_t(j * size_ + i)]; }
  // (A, B) at (n.v, roughness), bilinear between cell centres and clamped
  // at the outer ones: brdf.glsl's BrdfAlbedoTable.
  glm::vec2 Lookup(float nv, float roughness) const;
  // The cosine-weighted mean over n.v of Lookup: 2 int_0^1 (A, B)(mu) mu dmu
  // (the white-sky albedo split), midpoint rule in mu.
  glm::vec2 WhiteSky(float roughness) const;

 private:
  int size_ = 0;
  std::vector<glm::vec2> entries_;  // j * size + i
};

// The white-sky albedo of brdf.glsl's BRDF (BrdfUniformAlbedo averaged over
// n.v with weight 2 n.v): diffuse (1 - metallic) baseColor (1 - F_avg)^2,
// F_avg = F0 + (1 - F0) / 21 (Schlick's cosine-weighted mean, taken once
// for the view and once for the light), plus the specular F0 (A - B) + B
// with (A, B) = table.WhiteSky(roughness); F0 = mix(dielectric F0,
// baseColor, metallic), F90 = mix(dielectric F90, 1, metallic), the
// dielectric pair the material's (0.04 and 1 unless KHR_materials_ior /
// _specular say otherwise; F_avg = F0 + (F90 - F0) / 21 and the specular
// F0 (A - B) + F90 B then). A Lambertian surface (metallic 0, roughness 1,
// brdf.glsl's BrdfLambertian) returns baseColor unchanged.
glm::vec3 BrdfWhiteSkyAlbedo(const glm::vec3& base_color, float metallic, float roughness,
                             const glm::vec3& specular_f0 = glm::vec3(0.04f),
                             float specular_f90 = 1.0f);

// brdf.glsl's BrdfUniformAlbedo: the directional albedo seen from (or, by
// reciprocity, lit from) a direction at cosine `nv` to the normal, what the
// surface reflects of uniform incident light; baseColor for a Lambertian
// surface.
glm::vec3 BrdfDirectionalAlbedo(const glm::vec3& base_color, float metallic, float roughness,
                                float nv, const glm::vec3& specular_f0 = glm::vec3(0.04f),
                                float specular_f90 = 1.0f);

}  // namespace gistream
