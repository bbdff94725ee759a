#version 450 core
// Omnidirectional shadow map: one pass renders all six faces of a cube-map
// array entry (layered rendering through gl_Layer).
layout(triangles, invocations = 6) in;
layout(triangle_strip, max_vertices = 3) out;
uniform mat4 uFaceViewProj[6];
uniform int uCube;  // cube index in the array
out vec3 gWorld;
void main() {
  for (int i = 0; i < 3; ++i) {
    gWorld = gl_in[i].gl_Position.xyz;
    gl_Position = uFaceViewProj[gl_InvocationID] * gl_in[i].gl_Position;
    gl_Layer = uCube * 6 + gl_InvocationID;
    EmitVertex();
  }
  EndPrimitive();
}
