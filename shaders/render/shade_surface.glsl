// The solvers' final passes: read the view G-buffer at a pixel and shade
// it, L = L_emitted + L_direct + L_indirect. Lambertian surfaces (metallic
// 0, roughness 1): albedo / pi * (E_direct + E_indirect), with E_direct from
// render/direct_light.glsl and E_indirect the solver's. Glossy surfaces
// (common/brdf.glsl): direct light through the BRDF (DirectReflected); the
// solver's indirect irradiance as if it arrived from all directions alike,
// albedo(v) / pi * E_indirect with the BRDF's directional albedo, unless the
// solver passes its own glossy indirect radiance (ShadeGlossy).
#include "bindings.glsl"
#include "common/brdf.glsl"
#include "render/direct_light.glsl"
#include "render/gbuffer_read.glsl"

struct GSurface {
  vec3 position;
  vec3 normal;  // faces the viewer
  vec3 albedo;
  vec3 emission;
  float metallic;
  float roughness;
  vec4 specular;  // rgb: dielectric F0, a: F90
};

// The view's eye (render/gbuffer.h, bound by BeginShadePass).
layout(std140, binding = GS_UBO_VIEW) uniform View { vec4 uEye; };

// False where the pixel shows no geometry (background).
bool ReadGBuffer(ivec2 px, out GSurface s) {
  vec4 pos = texelFetch(uGPosition, px, 0);
  s.position = pos.xyz;
  s.normal = texelFetch(uGNormal, px, 0).xyz;
  vec4 albedo = texelFetch(uGAlbedo, px, 0);
  vec4 emission = texelFetch(uGEmission, px, 0);
  s.albedo = albedo.rgb;
  s.emission = emission.rgb;
  s.metallic = albedo.a;
  s.roughness = emission.a;
  s.specular = texelFetch(uGSpecular, px, 0);
  return pos.w != 0.0;
}

SurfaceBrdf SurfaceBrdfOf(GSurface s) {
  return SurfaceBrdf(s.albedo, s.metallic, s.roughness, s.specular);
}

// Unit direction from the surface to the eye.
vec3 ViewDirection(GSurface s) { return SafeNormalize(uEye.xyz - s.position, s.normal); }

// The solver's indirect irradiance scaled by uIndirectScale: 1, or k when
// every light was scaled by k since the solve (solvers/emission_scale.h).
uniform float uIndirectScale = 1.0;

// A glossy surface whose solver resolves the indirect light's direction:
// `l_indirect` is the reflected indirect radiance itself.
vec3 ShadeGlossy(GSurface s, vec3 l_indirect) {
  vec3 v = ViewDirection(s);
  vec3 direct = FiniteOrZero(DirectReflected(s.position, s.normal, v, SurfaceBrdfOf(s)));
  return s.emission + direct + uIndirectScale * FiniteOrZero(l_indirect);
}

vec3 ShadeSurface(GSurface s, vec3 e_indirect) {
  SurfaceBrdf b = SurfaceBrdfOf(s);
  if (BrdfLambertian(b)) {
    vec3 e_direct = FiniteOrZero(DirectIrradiance(s.position, s.normal));
    return s.emission + s.albedo * INV_PI * (e_direct + uIndirectScale * FiniteOrZero(e_indirect));
  }
  vec3 v = ViewDirection(s);
  return ShadeGlossy(s, BrdfUniformAlbedo(b, s.normal, v) * INV_PI * FiniteOrZero(e_indirect));
}
