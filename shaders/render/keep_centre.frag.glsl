#version 450 core
// The pixel-centre sample of an accumulation that can be carried
// (render/refinement.h): its radiance, and in alpha the distance from the
// eye to the surface it shows (0: background), which the show pass
// compares with the carried centre's to find the pixels whose surface
// changed (shaders/render/show_refined.frag.glsl).
#include "bindings.glsl"
layout(binding = GS_UNIT_HDR) uniform sampler2D uHdr;
layout(binding = GS_UNIT_GBUFFER_POSITION) uniform sampler2D uGPosition;  // w = 0: background
uniform vec3 uEye;
out vec4 oColor;
void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  const vec4 position = texelFetch(uGPosition, p, 0);
  oColor = vec4(texelFetch(uHdr, p, 0).rgb,
                position.w > 0.0 ? distance(position.xyz, uEye) : 0.0);
}
