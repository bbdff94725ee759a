#version 450 core
// display: L = L_emitted + albedo / pi * (E_direct + E_indirect), direct
// light per pixel (shadow maps, as `direct`), indirect interpolated from
// the vertices (Section 4.3.1, "For final display ...").
#include "implicit_visibility/bindings.glsl"
#include "render/shade_surface.glsl"
layout(binding = IV_UNIT_INDIRECT) uniform sampler2D uIndirect;  // rgb: E_indirect, a: 1 where drawn
in vec2 vUv;
out vec4 oRadiance;
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  GSurface s;
  if (!ReadGBuffer(px, s)) {
    oRadiance = vec4(s.emission, 1.0);  // the background (render/sky)
    return;
  }
  oRadiance = vec4(ShadeSurface(s, texelFetch(uIndirect, px, 0).rgb), 1.0);
}
