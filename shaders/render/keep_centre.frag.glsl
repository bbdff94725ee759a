#version 450 core
// The pixel-centre sample of an accumulation that can be carried
// (render/refinement.h): its radiance, and in alpha the distance from the
// eye to the surface it shows (0: background; negative on an emitter, so
// a lamp flush with a ceiling is not the ceiling), which the show pass
// compares with the carried centre's to find the pixels whose surface
// changed, and with a reprojected one's (shaders/render/show_refined.frag.glsl).
#include "bindings.glsl"
layout(binding = GS_UNIT_HDR) uniform sampler2D uHdr;
layout(binding = GS_UNIT_GBUFFER_POSITION) uniform sampler2D uGPosition;  // w = 0: background
layout(binding = GS_UNIT_GBUFFER_EMISSION) uniform sampler2D uGEmission;
uniform vec3 uEye;
out vec4 oColor;
void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  const vec4 position = texelFetch(uGPosition, p, 0);
  const bool emitter = any(greaterThan(texelFetch(uGEmission, p, 0).rgb, vec3(0.0)));
  const float d = position.w > 0.0 ? distance(position.xyz, uEye) : 0.0;
  oColor = vec4(texelFetch(uHdr, p, 0).rgb, emitter ? -d : d);
}
