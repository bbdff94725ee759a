#version 450 core
// A VPL's distance cube (solvers/avg/vpl_shadow_maps.cpp): as
// render/shadow_cube.geom.glsl, but one invocation per triangle that loops
// over the faces in the mask (a node is seen by one to three of the five
// faces a hemisphere reaches; llvmpipe runs each of six invocations apart).
layout(triangles) in;
layout(triangle_strip, max_vertices = 18) out;
uniform mat4 uFaceViewProj[6];
uniform int uCube;             // cube index in the array
uniform int uFaceMask = 0x3f;  // bit f: face f may see this draw (render/proxy_filters.h)
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
