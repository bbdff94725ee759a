#version 450 core
// illumination, the glossy nodes' pull-up (glossy.glsl): the internal
// nodes with slots in [uBegin, uEnd) of one height level take, per bin,
// the area-weighted average of their children's radiance in that bin (a
// child without a slot adds nothing: its light is diffuse, in pull.comp's
// radiance). One invocation per (slot, bin); levels run bottom-up.
#include "implicit_visibility/bindings.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = IV_GLOSSY_PULL_CHILDREN) readonly buffer Children { ivec4 children[]; };
layout(std430, binding = IV_GLOSSY_PULL_AREAS) readonly buffer Areas { float area[]; };
layout(std430, binding = IV_GLOSSY_PULL_NODE_SLOTS) readonly buffer NodeSlots { int node_slot[]; };
layout(std430, binding = IV_GLOSSY_PULL_SLOT_NODES) readonly buffer SlotNodes { int slot_node[]; };
layout(std430, binding = IV_GLOSSY_PULL_RADIANCE) buffer Radiance { vec4 radiance[]; };
uniform int uBegin;
uniform int uEnd;
uniform int uGlossyBins;
void main() {
  int id = int(gl_GlobalInvocationID.x);
  int slot = uBegin + id / uGlossyBins, bin = id % uGlossyBins;
  if (slot >= uEnd) return;
  ivec4 c = children[slot_node[slot]];
  vec3 sum = vec3(0.0);
  float total = 0.0;
  for (int k = 0; k < 4; ++k) {
    if (c[k] < 0) continue;
    int s = node_slot[c[k]];
    if (s >= 0) sum += area[c[k]] * radiance[s * uGlossyBins + bin].rgb;
    total += area[c[k]];
  }
  radiance[slot * uGlossyBins + bin] = vec4(total > 0.0 ? sum / total : vec3(0.0), 0.0);
}
