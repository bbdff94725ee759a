// Glossy elements (Dong et al. 2007, Section 4.3: "in case of glossy
// reflections, we augment our bin structure and store the outgoing
// radiance per direction in it"): a glossy leaf, and every node above one,
// has a slot holding the direct light it reflects per directional bin
// (hierarchy/directional_bins.h, shared with antiradiance), filled by
// render/glossy_bin_direct.comp.glsl and glossy_pull.comp.glsl. A link's
// source adds its slot's bin toward the receiver to its diffuse radiance.
#include "implicit_visibility/bindings.glsl"
struct GlossyNode {
  vec4 position;  // xyz the node's centre
  vec4 normal;    // xyz its unit normal
};
layout(std430, binding = IV_GATHER_NODE_SLOTS) readonly buffer NodeSlots { int node_slot[]; };
layout(std430, binding = IV_GATHER_GLOSSY_NODES) readonly buffer GlossyNodes { GlossyNode glossy_nodes[]; };
layout(std430, binding = IV_GATHER_GLOSSY_RADIANCE) readonly buffer GlossyRadiance { vec4 glossy_radiance[]; };
layout(std430, binding = IV_GATHER_BIN_LUT) readonly buffer BinLut { uint bin_lut[]; };
layout(std430, binding = IV_GATHER_LINK_BINS) readonly buffer LinkBins { uint link_bins[]; };
layout(std430, binding = IV_GATHER_RECEIVER_BINS) readonly buffer ReceiverBins { vec4 receiver_bins[]; };
uniform int uGlossyBins;  // 0: no glossy elements
uniform int uLutRes;

// DirectionalBins::Find: the bin nearest to unit d, through its cube-map
// table (the same face and texel arithmetic).
int GlossyBin(vec3 d) {
  vec3 a = abs(d);
  int face;
  float u, v, m;
  if (a.x >= a.y && a.x >= a.z) {
    face = d.x > 0.0 ? 0 : 1, m = a.x, u = d.y, v = d.z;
  } else if (a.y >= a.z) {
    face = d.y > 0.0 ? 2 : 3, m = a.y, u = d.x, v = d.z;
  } else {
    face = d.z > 0.0 ? 4 : 5, m = a.z, u = d.x, v = d.y;
  }
  int x = clamp(int(0.5 * (u / m + 1.0) * float(uLutRes)), 0, uLutRes - 1);
  int y = clamp(int(0.5 * (v / m + 1.0) * float(uLutRes)), 0, uLutRes - 1);
  return int(bin_lut[(face * uLutRes + y) * uLutRes + x]);
}

// The glossy radiance node `node` sends toward the receiver of link k:
// along the receiver's bin that link fills, reversed (the direction from
// the part of the source that bin sees; a near source spread over several
// of the receiver's bins is looked up toward each part, not from its
// centre alone). Zero for a node without a slot. A direction within a few
// degrees of the node's horizon is lifted above it: the bins below the
// horizon hold nothing, and a receiver seen at grazing angles would
// otherwise get no glossy light.
const float kGlossyHorizon = 0.1;
vec3 GlossyToward(int node, uint k) {
  int s = node_slot[node];
  if (s < 0) return vec3(0.0);
  GlossyNode g = glossy_nodes[s];
  uint bin = (link_bins[k >> 1] >> (16u * (k & 1u))) & 0xffffu;
  vec3 d = -receiver_bins[bin].xyz;
  float c = dot(d, g.normal.xyz);
  if (c < kGlossyHorizon) d = normalize(d + (kGlossyHorizon - c) * g.normal.xyz);
  return glossy_radiance[s * uGlossyBins + GlossyBin(d)].rgb;
}
