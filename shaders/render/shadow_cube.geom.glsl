#version 450 core
// Omnidirectional shadow map: one pass renders all six faces of a cube-map
// array entry (layered rendering through gl_Layer). One invocation per
// triangle loops over the faces in the mask: llvmpipe runs each of six
// invocations apart, and a culled draw reaches one to three faces
// (render/proxy_filters.h). Also avg's VPL distance cubes
// (solvers/avg/vpl_shadow_maps.cpp).
layout(triangles) in;
layout(triangle_strip, max_vertices = 18) out;
uniform mat4 uFaceViewProj[6];
uniform int uCube;             // cube index in the array
uniform int uFaceMask = 0x3f;  // bit f: face f may see this draw
out vec3 gWorld;
void main() {
  for (int f = 0; f < 6; ++f) {
    if ((uFaceMask & (1 << f)) == 0) continue;
    for (int i = 0; i < 3; ++i) {
      gWorld = gl_in[i].gl_Position.xyz;
      gl_Position = uFaceViewProj[f] * gl_in[i].gl_Position;
      gl_Layer = uCube * 6 + f;
      EmitVertex();
    }
    EndPrimitive();
  }
}
