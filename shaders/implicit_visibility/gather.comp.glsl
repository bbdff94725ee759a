#version 450 core
// illumination, one bounce (Section 4.3): every leaf gathers the radiance
// of the nodes its pushed-down links point to, E = E_env + sum w L (Eq. 5
// summed over the bins), and turns it into outgoing radiance with its
// albedo, L' = albedo / pi * (E_direct + E). Reads one radiance buffer,
// writes the other (Jacobi), so the order of the leaves does not matter.
// A glossy source adds the direct light it reflects toward the receiver
// (glossy.glsl); a glossy leaf's own direct light leaves through its bins,
// so its diffuse radiance is L' = albedo / pi * E.
#include "implicit_visibility/bindings.glsl"
#include "common/math.glsl"
#include "implicit_visibility/leaves.glsl"
#include "implicit_visibility/glossy.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = IV_GATHER_LEAVES) readonly buffer Leaves { Leaf leaves[]; };
layout(std430, binding = IV_GATHER_DIRECT_E) readonly buffer DirectE { vec4 e_direct[]; };
layout(std430, binding = IV_GATHER_ENV_E) readonly buffer EnvE { vec4 e_env[]; };
layout(std430, binding = IV_GATHER_OFFSETS) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = IV_GATHER_LINKS) readonly buffer Links { uvec2 links[]; };  // source, weight bits
layout(std430, binding = IV_GATHER_RADIANCE_IN) readonly buffer RadianceIn { vec4 radiance_in[]; };
layout(std430, binding = IV_GATHER_RADIANCE_OUT) writeonly buffer RadianceOut { vec4 radiance_out[]; };
layout(std430, binding = IV_GATHER_INDIRECT_E) writeonly buffer IndirectE { vec4 e_indirect[]; };
uniform int uLeafCount;
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= uLeafCount) return;
  Leaf leaf = leaves[i];
  vec3 e = e_env[i].rgb;
  for (uint k = offsets[i]; k < offsets[i + 1]; ++k) {
    uvec2 link = links[k];
    vec3 l = radiance_in[link.x].rgb;
    if (uGlossyBins > 0) l += GlossyToward(int(link.x), k);
    e += uintBitsToFloat(link.y) * l;
  }
  e = FiniteOrZero(e);
  e_indirect[i] = vec4(e, 0.0);
  vec3 source = uGlossyBins > 0 && leaf.normal.w >= 0.0 ? e : e_direct[i].rgb + e;
  radiance_out[i] = vec4(FiniteOrZero(leaf.albedo.rgb * INV_PI * source), 0.0);
}
