#version 450 core
// Omnidirectional shadow map: one pass renders all six faces of a cube-map
// array entry (layered rendering through gl_Layer).
layout(triangles, invocations = 6) in;
layout(triangle_strip, max_vertices = 3) out;
uniform mat4 uFaceViewProj[6];
uniform int uCube;  // cube index in the array
uniform int uFaceMask = 0x3f;  // bit f: face f may see this draw (render/proxy_filters.h)
out vec3 gWorld;
void main() {
  if ((uFaceMask & (1 << gl_InvocationID)) == 0) return;
  for (int i = 0; i < 3; ++i) {
    gWorld = gl_in[i].gl_Position.xyz;
    gl_Position = uFaceViewProj[gl_InvocationID] * gl_in[i].gl_Position;
    gl_Layer = uCube * 6 + gl_InvocationID;
    EmitVertex();
  }
  EndPrimitive();
}
