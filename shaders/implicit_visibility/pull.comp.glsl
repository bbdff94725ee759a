#version 450 core
// illumination, pull up (Section 4.3.1): the internal nodes of one height
// level [uBegin, uEnd) take the area-weighted average of their children's
// outgoing radiance. Levels run bottom-up, one dispatch each.
#include "implicit_visibility/bindings.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = IV_PULL_CHILDREN) readonly buffer Children { ivec4 children[]; };
layout(std430, binding = IV_PULL_AREAS) readonly buffer Areas { float area[]; };
layout(std430, binding = IV_PULL_RADIANCE) buffer Radiance { vec4 radiance[]; };
uniform int uBegin;
uniform int uEnd;
void main() {
  int node = uBegin + int(gl_GlobalInvocationID.x);
  if (node >= uEnd) return;
  ivec4 c = children[node];
  vec3 sum = vec3(0.0);
  float total = 0.0;
  for (int k = 0; k < 4; ++k) {
    if (c[k] < 0) continue;
    sum += area[c[k]] * radiance[c[k]].rgb;
    total += area[c[k]];
  }
  radiance[node] = vec4(total > 0.0 ? sum / total : vec3(0.0), 0.0);
}
