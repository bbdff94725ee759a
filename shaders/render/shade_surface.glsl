// The solvers' final passes: read the view G-buffer at a pixel and shade a
// Lambertian surface, L = L_emitted + albedo / pi * (E_direct + E_indirect),
// with E_direct from render/direct_light.glsl and E_indirect the solver's.
#include "render/direct_light.glsl"
#include "render/gbuffer_read.glsl"

struct GSurface {
  vec3 position;
  vec3 normal;  // faces the viewer
  vec3 albedo;
  vec3 emission;
};

// False where the pixel shows no geometry (background).
bool ReadGBuffer(ivec2 px, out GSurface s) {
  vec4 pos = texelFetch(uGPosition, px, 0);
  s.position = pos.xyz;
  s.normal = texelFetch(uGNormal, px, 0).xyz;
  s.albedo = texelFetch(uGAlbedo, px, 0).rgb;
  s.emission = texelFetch(uGEmission, px, 0).rgb;
  return pos.w != 0.0;
}

// The solver's indirect irradiance scaled by uIndirectScale: 1, or k when
// every light was scaled by k since the solve (solvers/emission_scale.h).
uniform float uIndirectScale = 1.0;

vec3 ShadeSurface(GSurface s, vec3 e_indirect) {
  vec3 e_direct = FiniteOrZero(DirectIrradiance(s.position, s.normal));
  return s.emission + s.albedo * INV_PI * (e_direct + uIndirectScale * FiniteOrZero(e_indirect));
}
