#version 450 core
// The shown coefficients follow the solution with hysteresis (sh_probes'
// progressive update): shown = mix(solution, shown, uHysteresis) once per
// frame, so probes re-rendered a few per frame fade in rather than jump.
// uScale != 1 scales both first (a dimmer's factor made the solution).
#include "sh_probes/bindings.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SH_BINDING_COEFFICIENTS) buffer Solution { vec4 solution[]; };
layout(std430, binding = SH_BINDING_SHOWN) buffer Shown { vec4 shown[]; };
uniform int uCount;
uniform float uHysteresis;
uniform float uScale;
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= uCount) return;
  vec4 s = solution[i] * uScale;
  solution[i] = s;
  shown[i] = mix(s, shown[i] * uScale, uHysteresis);
}
