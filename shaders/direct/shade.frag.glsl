#version 450 core
// `direct` solver, shade stage: outgoing radiance of a Lambertian surface,
// L = albedo / pi * E_direct + L_emitted.
#include "render/direct_light.glsl"
#include "render/gbuffer_read.glsl"
uniform vec3 uBackground;
in vec2 vUv;
out vec4 oRadiance;
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec4 pos = texelFetch(uGPosition, px, 0);
  if (pos.w == 0.0) {
    oRadiance = vec4(uBackground, 1.0);
    return;
  }
  vec3 n = texelFetch(uGNormal, px, 0).xyz;
  vec3 albedo = texelFetch(uGAlbedo, px, 0).rgb;
  vec3 emission = texelFetch(uGEmission, px, 0).rgb;
  vec3 l = albedo * INV_PI * DirectIrradiance(pos.xyz, n) + emission;
  oRadiance = vec4(l, 1.0);
}
