#version 450 core
// Omnidirectional shadow map without layered vertex output
// (shadow_cube.vert.glsl): each triangle into the faces in vFaces (its
// draw record's one face, or all six item by item), into cube uCube of a
// cube-map array through gl_Layer. One invocation per triangle: llvmpipe
// runs a geometry shader's invocations apart.
layout(triangles) in;
layout(triangle_strip, max_vertices = 18) out;
uniform mat4 uFaceViewProj[6];
uniform int uCube;  // cube index in the array
flat in int vFaces[];
out vec3 gWorld;
void main() {
  for (int f = 0; f < 6; ++f) {
    if ((vFaces[0] & (1 << f)) == 0) continue;
    for (int i = 0; i < 3; ++i) {
      gWorld = gl_in[i].gl_Position.xyz;
      gl_Position = uFaceViewProj[f] * gl_in[i].gl_Position;
      gl_Layer = uCube * 6 + f;
      EmitVertex();
    }
    EndPrimitive();
  }
}
