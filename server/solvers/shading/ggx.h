// The path tracer's BRDF: glTF 2.0 metallic-roughness (glTF 2.0 Appendix B)
// as a GGX microfacet specular lobe over a Lambertian diffuse one. The GLSL
// twin that the rasterizing solvers shade with is shaders/common/brdf.glsl;
// tests/unit/ggx_test.cpp checks this one against the analytic
// normalisations, the GL tests check the twin against this one.
//
//   f = D G2 F / (4 n.l n.v) + (1 - F(n.v)) (1 - F(n.l)) (1 - metallic) baseColor / pi
//   D   Trowbridge-Reitz (GGX), alpha = roughness^2 (Walter et al. 2007, eq. 33)
//   G2  Smith height-correlated masking-shadowing (Heitz 2014, eq. 99)
//   F   Schlick, F0 + (F90 - F0) (1 - c)^5 with F0 = mix(dielectric F0,
//       baseColor, metallic), F90 = mix(dielectric F90, 1, metallic); at
//       v.h in the specular lobe. The dielectric F0 and F90 are 0.04 and 1
//       (ior 1.5) unless KHR_materials_ior / KHR_materials_specular say
//       otherwise: F0 = min(((ior - 1) / (ior + 1))^2 specularColorFactor,
//       1) specularFactor, F90 = specularFactor (the extensions' specs).
//
// The diffuse lobe's Fresnel weight: glTF's (1 - F(v.h)) lets a white
// dielectric reflect more than it receives at grazing views (directional
// albedo 1.35 at roughness 0.25, view cosine 0.1; measured with
// ggx_test.cpp), so the diffuse lobe here takes what enters and what
// leaves, (1 - F(n.v)) (1 - F(n.l)) (as Ashikhmin and Shirley 2000 couple
// their lobes): reciprocal, and the furnace stays at or below 1. The price
// is a dark rim on rough dielectrics: a white one's albedo falls to 0.41
// at view cosine 0.1 and roughness 1 (0.89 head-on).
//
// Energy: single scattering only. Light that would leave after more than
// one bounce between microfacets is lost, so the directional albedo of a
// white metal falls below 1 as roughness grows: 0.31 seen head-on at
// roughness 1 (exactly 1 - ln 2 there, where D = 1/pi and G2/(4 n.l n.v) =
// 1/(2 (n.l + n.v))), 0.63 at roughness 0.75, 0.92 at 0.5, 0.99 at 0.25;
// ggx_test.cpp prints the table. No multiple-scattering compensation yet.
//
// metallic 0 and roughness 1 is the Lambertian surface (f = baseColor / pi)
// exactly: the material of every scene made before glossy surfaces existed
// and of the default material. The formula above would give that surface a
// rough 4% specular layer and a Fresnel-weighted diffuse one (a 0.8 grey's
// albedo would be 0.71 head-on, 0.34 at view cosine 0.1); Lambertian()
// names the exception.
#pragma once

#include <glm/glm.hpp>

namespace gistream::shading {

// Roughness below this is clamped: alpha >= kMinRoughness^2 keeps D finite
// (at most 1 / (pi alpha^2) ~ 4e5) for mirror-like materials.
inline constexpr float kMinRoughness = 0.03f;

struct Brdf {
  glm::vec3 base_color{1.0f};  // linear, [0, 1]
  float metallic = 0.0f;       // [0, 1]
  float roughness = 1.0f;      // perceptual, [0, 1]
  // The dielectric part's Fresnel at normal and grazing incidence (see above).
  glm::vec3 specular_f0{0.04f};
  float specular_f90 = 1.0f;

  bool Lambertian() const { return metallic == 0.0f && roughness == 1.0f; }
  float alpha() const;
  glm::vec3 f0() const { return glm::mix(specular_f0, base_color, metallic); }
  glm::vec3 f90() const { return glm::vec3(specular_f90 + (1.0f - specular_f90) * metallic); }
};

// The microfacet terms, with cosines against the normal (z in the local frame).
float GgxD(float cos_h, float alpha);
// Smith G1 of GGX: masking of one direction.
float SmithG1(float cos_v, float alpha);
// G2 / (4 cos_v cos_l), height-correlated (Heitz 2014, eq. 99).
float SmithVisibility(float cos_v, float cos_l, float alpha);
glm::vec3 Schlick(const glm::vec3& f0, const glm::vec3& f90, float cos_vh);
// The diffuse lobe's weight (1 - F(n.v)) (1 - F(n.l)) (see above).
glm::vec3 DiffuseTransmission(const Brdf& brdf, float cos_o, float cos_i);

// BRDF value (no cosine) in the local frame (z: shading normal); zero unless
// both directions are above the surface.
glm::vec3 Eval(const Brdf& brdf, const glm::vec3& wo, const glm::vec3& wi);

// Probability of choosing the specular lobe when sampling from wo.
float SpecularChance(const Brdf& brdf, const glm::vec3& wo);

// Solid-angle pdf of Sample returning wi: a mixture of visible-normal
// sampling of the GGX lobe (Heitz 2018) and cosine sampling of the diffuse
// one, weighted by SpecularChance.
float Pdf(const Brdf& brdf, const glm::vec3& wo, const glm::vec3& wi);

struct BrdfSample {
  glm::vec3 wi{0.0f};      // local frame
  glm::vec3 weight{0.0f};  // f cos / pdf
  float pdf = 0.0f;        // 0: no sample (below the surface)
};
// Draws wi from wo with the uniforms u (x picks the lobe).
BrdfSample Sample(const Brdf& brdf, const glm::vec3& wo, const glm::vec3& u);

// A GGX visible normal for wo (Heitz 2018, "Sampling the GGX Distribution
// of Visible Normals", listing 1); pdf G1(wo) max(0, wo.h) D(h) / wo.z.
glm::vec3 SampleVisibleNormal(const glm::vec3& wo, float alpha, float u1, float u2);

}  // namespace gistream::shading
