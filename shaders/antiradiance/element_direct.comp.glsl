#version 450 core
// Direct irradiance at every leaf element's centre through the shared
// shadow maps (Dachsbacher et al. 2007, Section 3.3: direct light
// initializes the elements and creates no antiradiance).
#include "antiradiance/bindings.glsl"
layout(local_size_x = 64) in;
#include "render/direct_light.glsl"
#include "antiradiance/elements.glsl"
layout(std430, binding = AR_BINDING_ELEMENT_DIRECT) writeonly buffer ElementDirect { vec4 element_direct[]; };
uniform int uCount;
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= uCount) return;
  Element e = elements[i];
  element_direct[i] = vec4(FiniteOrZero(DirectIrradiance(e.position_radius.xyz, e.normal.xyz)), 0.0);
}
