#version 450 core
// The HDR target's texel at this pixel (refinement: blended into the
// accumulation by render/view_passes.cpp, weight 1 / samples).
#include "bindings.glsl"
layout(binding = GS_UNIT_HDR) uniform sampler2D uHdr;
out vec4 oColor;
void main() { oColor = texelFetch(uHdr, ivec2(gl_FragCoord.xy), 0); }
