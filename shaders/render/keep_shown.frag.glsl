#version 450 core
// The picture shown before a camera move (render/refinement.h,
// `reproject`): its radiance, and in alpha the distance from that camera's
// eye to the surface its pixel-centre sample showed (kept in the history
// target by keep_centre.frag.glsl; 0: background), which the show pass
// compares with the distance to the surface a pixel of the new view
// reprojects onto (shaders/render/show_refined.frag.glsl). The centre's,
// not the last sample's: on an edge that one may have seen the other side.
#include "bindings.glsl"
layout(binding = GS_UNIT_HDR) uniform sampler2D uHdr;
layout(binding = GS_UNIT_REFINE_HISTORY) uniform sampler2D uCentre;
out vec4 oColor;
void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  oColor = vec4(texelFetch(uHdr, p, 0).rgb, texelFetch(uCentre, p, 0).a);
}
