#version 450 core
// `direct` solver, shade stage: outgoing radiance of a Lambertian surface,
// L = albedo / pi * E_direct + L_emitted.
#include "render/shade_surface.glsl"
in vec2 vUv;
out vec4 oRadiance;
void main() {
  GSurface s;
  oRadiance = ReadGBuffer(ivec2(gl_FragCoord.xy), s) ? vec4(ShadeSurface(s, vec3(0.0)), 1.0)
                                                    : vec4(s.emission, 1.0);
}
