#version 450 core
// display: L = L_emitted + albedo / pi * (E_direct + E_indirect), direct
// light per pixel (shadow maps, as `direct`), indirect interpolated from
// the vertices (Section 4.3.1, "For final display ...").
#include "render/direct_light.glsl"
#include "render/gbuffer_read.glsl"
layout(binding = 13) uniform sampler2D uIndirect;  // rgb: E_indirect, a: 1 where drawn
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
  vec3 e_indirect = FiniteOrZero(texelFetch(uIndirect, px, 0).rgb);
  vec3 e_direct = FiniteOrZero(DirectIrradiance(pos.xyz, n));
  oRadiance = vec4(emission + albedo * INV_PI * (e_direct + e_indirect), 1.0);
}
