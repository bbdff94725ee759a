#version 450 core
#extension GL_ARB_shader_viewport_layer_array : require
// The pieces of a tessellated proxy triangle (vpl_shadow.tesc.glsl),
// projected into their VPL's paraboloid map (layer = VPL) as
// vpl_shadow.geom.glsl does for whole triangles, without a geometry shader:
// the part behind the VPL's hemisphere is clipped by gl_ClipDistance[0]
// (the local z, linear along a piece, so the cut lies where the piece
// crosses z = 0; its uv is the chord's, within the piece's sagitta).
#include "avg/vpl.glsl"
layout(triangles, equal_spacing, ccw) in;
flat in int tVpl[];
out vec3 gLocal;
flat out float gFar;
void main() {
  vec3 c = gl_TessCoord;
  vec3 world = c.x * gl_in[0].gl_Position.xyz + c.y * gl_in[1].gl_Position.xyz +
               c.z * gl_in[2].gl_Position.xyz;
  Vpl v = vpls[tVpl[0]];
  vec3 local = VplLocal(v, world - v.position_far.xyz);
  float dist = max(length(local), 1e-30);
  float far = v.position_far.w;
  gLocal = local;
  gFar = far;
  gl_Position = vec4(ParaboloidUv(local / dist), clamp(dist / far, 0.0, 1.0) * 2.0 - 1.0, 1.0);
  gl_ClipDistance[0] = local.z;
  gl_Layer = int(v.normal_layer.w);
}
