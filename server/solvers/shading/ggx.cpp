#include "solvers/shading/ggx.h"

#include <algorithm>
#include <cmath>

#include "solvers/shading/sampling.h"
#include "util/constants.h"

namespace gistream::shading {
namespace {

// The diffuse lobe's weight without the Fresnel factor: (1 - metallic) baseColor.
glm::vec3 DiffuseColor(const Brdf& brdf) { return (1.0f - brdf.metallic) * brdf.base_color; }

glm::vec3 CosineLocal(float u1, float u2) {
  const float r = std::sqrt(u1);
  const float phi = 2.0f * kPi * u2;
  return glm::vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1)));
}

}  // namespace

glm::vec3 DiffuseTransmission(const Brdf& brdf, float cos_o, float cos_i) {
  const glm::vec3 f0 = brdf.f0(), f90 = brdf.f90();
  return (glm::vec3(1.0f) - Schlick(f0, f90, cos_o)) * (glm::vec3(1.0f) - Schlick(f0, f90, cos_i));
}

float Brdf::alpha() const {
  const float r = std::clamp(roughness, kMinRoughness, 1.0f);
  return r * r;  // glTF 2.0 Appendix B: alpha = roughness^2
}

float GgxD(float cos_h, float alpha) {
  if (cos_h <= 0.0f) return 0.0f;
  // Walter et al. 2007, eq. 33: D = alpha^2 / (pi (cos^2 (alpha^2 - 1) + 1)^2).
  const float a2 = alpha * alpha;
  const float d = cos_h * cos_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

float SmithG1(float cos_v, float alpha) {
  if (cos_v <= 0.0f) return 0.0f;
  // Heitz 2014, eq. 34 with GGX's Lambda: 2 cos / (cos + sqrt(a^2 + (1 - a^2) cos^2)).
  const float a2 = alpha * alpha;
  return 2.0f * cos_v / (cos_v + std::sqrt(a2 + (1.0f - a2) * cos_v * cos_v));
}

float SmithVisibility(float cos_v, float cos_l, float alpha) {
  if (cos_v <= 0.0f || cos_l <= 0.0f) return 0.0f;
  // Heitz 2014, eq. 99, G2 = 1 / (1 + Lambda(v) + Lambda(l)), divided by
  // 4 cos_v cos_l (the form of Filament's V_SmithGGXCorrelated).
  const float a2 = alpha * alpha;
  const float gv = cos_l * std::sqrt(cos_v * cos_v * (1.0f - a2) + a2);
  const float gl = cos_v * std::sqrt(cos_l * cos_l * (1.0f - a2) + a2);
  return 0.5f / (gv + gl);
}

glm::vec3 Schlick(const glm::vec3& f0, const glm::vec3& f90, float cos_vh) {
  const float m = std::clamp(1.0f - cos_vh, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0 + (f90 - f0) * (m2 * m2 * m);
}

glm::vec3 Eval(const Brdf& brdf, const glm::vec3& wo, const glm::vec3& wi) {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
  if (brdf.Lambertian()) return brdf.base_color / kPi;
  const glm::vec3 h = glm::normalize(wo + wi);
  const float alpha = brdf.alpha();
  const glm::vec3 f = Schlick(brdf.f0(), brdf.f90(), glm::dot(wo, h));
  const glm::vec3 specular = f * (GgxD(h.z, alpha) * SmithVisibility(wo.z, wi.z, alpha));
  return specular + DiffuseTransmission(brdf, wo.z, wi.z) * DiffuseColor(brdf) / kPi;
}

float SpecularChance(const Brdf& brdf, const glm::vec3& wo) {
  if (brdf.Lambertian()) return 0.0f;
  // Each lobe's share of the light leaving at wo, estimated with the
  // Fresnel factor at the normal; the diffuse lobe keeps at least 1/4 of
  // the samples where it reflects anything.
  const glm::vec3 f = Schlick(brdf.f0(), brdf.f90(), std::max(wo.z, 0.0f));
  const float s = Luminance(f);
  const float d = Luminance((glm::vec3(1.0f) - f) * DiffuseColor(brdf));
  if (!(d > 0.0f)) return 1.0f;
  return std::min(s / (s + d), 0.75f);
}

float Pdf(const Brdf& brdf, const glm::vec3& wo, const glm::vec3& wi) {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  const float diffuse = wi.z / kPi;
  const float p = SpecularChance(brdf, wo);
  if (p <= 0.0f) return diffuse;
  const glm::vec3 h = glm::normalize(wo + wi);
  const float alpha = brdf.alpha();
  // Visible normals: pdf(h) = G1(wo) (wo.h) D(h) / wo.z; reflection's
  // Jacobian 1 / (4 wo.h) (Heitz 2018, eq. 17).
  const float specular = SmithG1(wo.z, alpha) * GgxD(h.z, alpha) / (4.0f * wo.z);
  return p * specular + (1.0f - p) * diffuse;
}

glm::vec3 SampleVisibleNormal(const glm::vec3& wo, float alpha, float u1, float u2) {
  // Heitz 2018, listing 1: the view direction in the hemisphere
  // configuration, a point on the projected disc, back to the ellipsoid.
  const glm::vec3 vh = glm::normalize(glm::vec3(alpha * wo.x, alpha * wo.y, wo.z));
  const float lensq = vh.x * vh.x + vh.y * vh.y;
  const glm::vec3 t1 =
      lensq > 0.0f ? glm::vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq) : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 t2 = glm::cross(vh, t1);
  const float r = std::sqrt(u1);
  const float phi = 2.0f * kPi * u2;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1.0f + vh.z);
  const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * std::sin(phi);
  const glm::vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(glm::vec3(alpha * nh.x, alpha * nh.y, std::max(0.0f, nh.z)));
}

BrdfSample Sample(const Brdf& brdf, const glm::vec3& wo, const glm::vec3& u) {
  BrdfSample out;
  if (wo.z <= 0.0f) return out;
  if (brdf.Lambertian()) {
    out.wi = CosineLocal(u.y, u.z);
    out.pdf = out.wi.z / kPi;
    out.weight = brdf.base_color;  // f cos / pdf
    if (!(out.wi.z > 0.0f)) out.pdf = 0.0f;
    return out;
  }
  if (u.x < SpecularChance(brdf, wo)) {
    const glm::vec3 h = SampleVisibleNormal(wo, brdf.alpha(), u.y, u.z);
    out.wi = 2.0f * glm::dot(wo, h) * h - wo;
  } else {
    out.wi = CosineLocal(u.y, u.z);
  }
  if (!(out.wi.z > 0.0f)) return out;
  out.pdf = Pdf(brdf, wo, out.wi);
  if (!(out.pdf > 0.0f) || !std::isfinite(out.pdf)) {
    out.pdf = 0.0f;
    return out;
  }
  out.weight = Eval(brdf, wo, out.wi) * (out.wi.z / out.pdf);
  return out;
}

}  // namespace gistream::shading
