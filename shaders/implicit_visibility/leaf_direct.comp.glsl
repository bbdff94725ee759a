#version 450 core
// illumination, first step: the direct irradiance at every leaf from the
// shadow-mapped lights (the same DirectIrradiance as `direct`), plus the
// environment through the leaf's open bins (Section 4.4); the leaves'
// first outgoing radiance L = albedo / pi * E (the first bounce's source;
// a glossy leaf's direct light leaves through its bins, glossy.glsl, so
// only the environment's here).
#include "implicit_visibility/bindings.glsl"
#include "render/direct_light.glsl"
#include "implicit_visibility/leaves.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = IV_LEAF_LEAVES) readonly buffer Leaves { Leaf leaves[]; };
layout(std430, binding = IV_LEAF_DIRECT_E) writeonly buffer DirectE { vec4 e_direct[]; };
layout(std430, binding = IV_LEAF_ENV_E) readonly buffer EnvE { vec4 e_env[]; };
layout(std430, binding = IV_LEAF_RADIANCE) writeonly buffer Radiance { vec4 radiance[]; };
uniform int uLeafCount;
uniform int uGlossy;  // the glossy leaves' bins hold their direct light (else: diffuse)
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= uLeafCount) return;
  Leaf l = leaves[i];
  vec3 e = FiniteOrZero(DirectIrradiance(l.position.xyz, l.normal.xyz));
  e_direct[i] = vec4(e, 0.0);
  vec3 diffuse = uGlossy != 0 && l.normal.w >= 0.0 ? vec3(0.0) : e;
  radiance[i] = vec4(FiniteOrZero(l.albedo.rgb * INV_PI * (diffuse + e_env[i].rgb)), 0.0);
}
