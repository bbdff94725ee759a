#version 450 core
// display: the leaves' indirect irradiance at the display mesh's vertices,
// interpolated over the triangles by the rasterizer. A vertex is a leaf
// (weights 1, 0, 0) or a full-mesh vertex over the proxy elements' nearest
// triangle (its barycentrics; hierarchy/vertex_transfer.h).
#include "implicit_visibility/bindings.glsl"
layout(location = 0) in vec3 aPosition;  // world
layout(location = 1) in uvec3 aLeaves;
layout(location = 2) in vec3 aWeights;
layout(std430, binding = IV_VERTEX_INDIRECT_E) readonly buffer IndirectE { vec4 e_indirect[]; };
uniform mat4 uViewProj;
out vec3 vIrradiance;
void main() {
  vIrradiance = aWeights.x * e_indirect[aLeaves.x].rgb;
  if (aWeights.y > 0.0) vIrradiance += aWeights.y * e_indirect[aLeaves.y].rgb;
  if (aWeights.z > 0.0) vIrradiance += aWeights.z * e_indirect[aLeaves.z].rgb;
  gl_Position = uViewProj * vec4(aPosition, 1.0);
}
