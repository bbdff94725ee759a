// glTF metallic-roughness BRDF, the GLSL twin of the path tracer's
// solvers/shading/ggx.h (the formulas, the Fresnel coupling of the
// diffuse lobe and the energy loss are explained there):
//   f = D G2 F / (4 n.l n.v) + (1 - F(n.v)) (1 - F(n.l)) (1 - metallic) baseColor / pi
// D: GGX (Walter et al. 2007, eq. 33), alpha = roughness^2; G2: Smith
// height-correlated (Heitz 2014, eq. 99); F: Schlick at v.h, F0 + (F90 -
// F0) (1 - c)^5, F0 = mix(dielectric F0, baseColor, metallic), F90 =
// mix(dielectric F90, 1, metallic), the dielectric pair the material's
// (0.04 and 1 unless KHR_materials_ior / _specular set them; ggx.h).
// Metallic 0 and roughness 1 is exactly
// Lambert. Shared by direct light (render/direct_light.glsl) and the final
// shade pass (render/shade_surface.glsl).
#include "common/brdf_albedo_table.glsl"
#include "common/math.glsl"

struct SurfaceBrdf {
  vec3 base_color;  // linear, [0, 1]
  float metallic;   // [0, 1]
  float roughness;  // perceptual, [0, 1]
  vec4 specular;    // rgb: dielectric F0, a: dielectric F90
};

// The dielectric F0 and F90 of a material that does not say (ior 1.5).
const vec4 BRDF_DEFAULT_SPECULAR = vec4(0.04, 0.04, 0.04, 1.0);

// A BRDF with the default dielectric layer: for the solvers' own elements
// (probe texels, VPLs, patches) that carry no per-material F0 and F90.
SurfaceBrdf DefaultSpecularBrdf(vec3 base_color, float metallic, float roughness) {
  return SurfaceBrdf(base_color, metallic, roughness, BRDF_DEFAULT_SPECULAR);
}

const float BRDF_MIN_ROUGHNESS = 0.03;  // ggx.h kMinRoughness

bool BrdfLambertian(SurfaceBrdf b) { return b.metallic == 0.0 && b.roughness == 1.0; }

float BrdfAlpha(SurfaceBrdf b) {
  float r = clamp(b.roughness, BRDF_MIN_ROUGHNESS, 1.0);
  return r * r;
}

vec3 BrdfF0(SurfaceBrdf b) { return mix(b.specular.rgb, b.base_color, b.metallic); }
vec3 BrdfF90(SurfaceBrdf b) { return vec3(mix(b.specular.a, 1.0, b.metallic)); }

vec3 BrdfSchlick(vec3 f0, vec3 f90, float c) {
  float m = clamp(1.0 - c, 0.0, 1.0);
  float m2 = m * m;
  return f0 + (f90 - f0) * (m2 * m2 * m);
}

float GgxD(float cos_h, float alpha) {
  if (cos_h <= 0.0) return 0.0;
  float a2 = alpha * alpha;
  float d = cos_h * cos_h * (a2 - 1.0) + 1.0;
  return a2 / (PI * d * d);
}

// G2 / (4 n.v n.l), height-correlated (Heitz 2014, eq. 99).
float SmithVisibility(float cos_v, float cos_l, float alpha) {
  if (cos_v <= 0.0 || cos_l <= 0.0) return 0.0;
  float a2 = alpha * alpha;
  float gv = cos_l * sqrt(cos_v * cos_v * (1.0 - a2) + a2);
  float gl = cos_v * sqrt(cos_l * cos_l * (1.0 - a2) + a2);
  return 0.5 / (gv + gl);
}

// f(v, l) (no cosine); n, v, l unit, world space; 0 below the surface.
vec3 BrdfEval(SurfaceBrdf b, vec3 n, vec3 v, vec3 l) {
  float nv = dot(n, v), nl = dot(n, l);
  if (nv <= 0.0 || nl <= 0.0) return vec3(0.0);
  if (BrdfLambertian(b)) return b.base_color * INV_PI;
  vec3 h = normalize(v + l);
  float alpha = BrdfAlpha(b);
  vec3 f0 = BrdfF0(b), f90 = BrdfF90(b);
  vec3 specular =
      BrdfSchlick(f0, f90, dot(v, h)) * (GgxD(dot(n, h), alpha) * SmithVisibility(nv, nl, alpha));
  vec3 diffuse = (1.0 - BrdfSchlick(f0, f90, nv)) * (1.0 - BrdfSchlick(f0, f90, nl)) *
                 ((1.0 - b.metallic) * INV_PI) * b.base_color;
  return specular + diffuse;
}

// The specular lobe's (A, B) at (n.v, roughness): bilinear in the
// generated table between its cell centres, clamped at the outer ones.
vec2 BrdfAlbedoTable(float nv, float roughness) {
  vec2 x = clamp(vec2(nv, roughness) * float(BRDF_TABLE_SIZE) - 0.5, vec2(0.0),
                 vec2(float(BRDF_TABLE_SIZE - 1)));
  ivec2 i0 = ivec2(floor(x));
  ivec2 i1 = min(i0 + 1, ivec2(BRDF_TABLE_SIZE - 1));
  vec2 t = x - vec2(i0);
  vec2 a = mix(BRDF_ALBEDO_TABLE[i0.y * BRDF_TABLE_SIZE + i0.x],
               BRDF_ALBEDO_TABLE[i0.y * BRDF_TABLE_SIZE + i1.x], t.x);
  vec2 b = mix(BRDF_ALBEDO_TABLE[i1.y * BRDF_TABLE_SIZE + i0.x],
               BRDF_ALBEDO_TABLE[i1.y * BRDF_TABLE_SIZE + i1.x], t.x);
  return mix(a, b, t.y);
}

// Directional albedo from v under uniform incident light: what a glossy
// receiver reflects of irradiance E that arrives from all directions
// alike, L = albedo(v) E / pi. The diffuse lobe exactly:
// (1 - metallic) baseColor (1 - F(n.v)) (1 - F_avg), F_avg = F0 + (F90 - F0) / 21
// the cosine-weighted mean of Schlick's factor; the specular lobe from the
// table of tools/make_brdf_table.py, E = F0 (A - B) + F90 B (ggx_test.cpp
// checks the table; A and B integrate the lobe without Fresnel and with
// (1 - v.h)^5, so any F0 and F90 share it). Lambertian surfaces: baseColor.
vec3 BrdfUniformAlbedo(SurfaceBrdf b, vec3 n, vec3 v) {
  if (BrdfLambertian(b)) return b.base_color;
  float nv = clamp(dot(n, v), 0.0, 1.0);
  vec3 f0 = BrdfF0(b), f90 = BrdfF90(b);
  vec3 diffuse = (1.0 - b.metallic) * b.base_color * (1.0 - BrdfSchlick(f0, f90, nv)) *
                 (1.0 - (f0 + (f90 - f0) / 21.0));
  vec2 ab = BrdfAlbedoTable(nv, b.roughness);
  return diffuse + f0 * (ab.x - ab.y) + f90 * ab.y;
}
