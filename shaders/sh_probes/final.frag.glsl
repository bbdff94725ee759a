#version 450 core
// final: L = L_emitted + albedo / pi * (E_direct + E_indirect), E_indirect
// interpolated from the probe grid (Section 3, step 6).
#include "render/direct_light.glsl"
#include "sh_probes/probe_grid.glsl"
#include "render/gbuffer_read.glsl"
in vec2 vUv;
out vec4 oRadiance;
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec4 pos = texelFetch(uGPosition, px, 0);
  if (pos.w == 0.0) {
    oRadiance = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  vec3 n = texelFetch(uGNormal, px, 0).xyz;
  vec3 albedo = texelFetch(uGAlbedo, px, 0).rgb;
  vec3 emission = texelFetch(uGEmission, px, 0).rgb;
  vec3 e_indirect = GridIrradiance(pos.xyz, n);
  vec3 e_direct = FiniteOrZero(DirectIrradiance(pos.xyz, n));
  vec3 l = emission + albedo * INV_PI * (e_direct + e_indirect);
  oRadiance = vec4(l, 1.0);
}
