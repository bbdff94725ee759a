#version 450 core
// final: L = L_emitted + albedo / pi * (E_direct + E_indirect), E_indirect
// interpolated from the probe grid (Section 3, step 6).
#include "render/shade_surface.glsl"
#include "sh_probes/probe_grid.glsl"
in vec2 vUv;
out vec4 oRadiance;
void main() {
  GSurface s;
  if (!ReadGBuffer(ivec2(gl_FragCoord.xy), s)) {
    oRadiance = vec4(s.emission, 1.0);  // the background (render/sky)
    return;
  }
  oRadiance = vec4(ShadeSurface(s, GridIrradiance(s.position, s.normal)), 1.0);
}
