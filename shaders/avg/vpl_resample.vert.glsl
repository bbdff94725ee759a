#version 450 core
#extension GL_ARB_shader_viewport_layer_array : require
// One full-screen triangle per VPL of a batch (instance i: VPL uFirstVpl + i,
// distance cube i), drawn into that VPL's paraboloid map layer.
#include "avg/vpl.glsl"
uniform int uFirstVpl;
flat out int vVpl;
flat out int vCube;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
  vVpl = uFirstVpl + gl_InstanceID;
  vCube = gl_InstanceID;
  gl_Layer = int(vpls[vVpl].normal_layer.w);
}
