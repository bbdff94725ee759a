#version 450 core
// display: the leaves' indirect irradiance at the mesh vertices (a leaf is
// a vertex), interpolated over the triangles by the rasterizer.
layout(location = 0) in vec3 aPosition;  // world
layout(std430, binding = 1) readonly buffer IndirectE { vec4 e_indirect[]; };
uniform mat4 uViewProj;
out vec3 vIrradiance;
void main() {
  vIrradiance = e_indirect[gl_VertexID].rgb;
  gl_Position = uViewProj * vec4(aPosition, 1.0);
}
