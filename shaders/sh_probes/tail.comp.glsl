#version 450 core
// Optional geometric tail: with bounce increments shrinking by a ratio r,
// the bounces not run add r / (1 - r) times the last increment.
#include "sh_probes/bindings.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SH_BINDING_COEFFICIENTS) buffer ShCoefficients { vec4 coefficients[]; };
layout(std430, binding = SH_BINDING_PREVIOUS) readonly buffer Previous { vec4 previous[]; };
uniform int uCount;
uniform float uScale;  // r / (1 - r)
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= uCount) return;
  coefficients[i] += uScale * (coefficients[i] - previous[i]);
}
