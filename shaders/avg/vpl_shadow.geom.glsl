#version 450 core
// Projects a triangle into its VPL's paraboloid map (layer = VPL): clipped
// to the VPL's upper hemisphere first, since the paraboloid map of a point
// behind the VPL is undefined.
#include "avg/vpl.glsl"
layout(triangles) in;
layout(triangle_strip, max_vertices = 4) out;
flat in int vVpl[];
out vec3 gLocal;
flat out float gFar;

void Emit(vec3 local, float far, int layer) {
  float dist = max(length(local), 1e-30);
  gLocal = local;
  gFar = far;
  gl_Position = vec4(ParaboloidUv(local / dist), clamp(dist / far, 0.0, 1.0) * 2.0 - 1.0, 1.0);
  gl_Layer = layer;
  EmitVertex();
}

void main() {
  Vpl v = vpls[vVpl[0]];
  vec3 p[3];
  for (int i = 0; i < 3; ++i) p[i] = VplLocal(v, gl_in[i].gl_Position.xyz - v.position_far.xyz);
  if (p[0].z < 0.0 && p[1].z < 0.0 && p[2].z < 0.0) return;
  // Sutherland-Hodgman against z >= 0: at most 4 vertices.
  vec3 q[4];
  int count = 0;
  for (int i = 0; i < 3; ++i) {
    vec3 a = p[i], b = p[(i + 1) % 3];
    if (a.z >= 0.0) q[count++] = a;
    if ((a.z >= 0.0) != (b.z >= 0.0)) q[count++] = mix(a, b, a.z / (a.z - b.z));
  }
  float far = v.position_far.w;
  int layer = int(v.normal_layer.w);
  // Polygon 0,1,2,3 as a strip 0,1,3,2.
  Emit(q[0], far, layer);
  Emit(q[1], far, layer);
  if (count == 4) {
    Emit(q[3], far, layer);
    Emit(q[2], far, layer);
  } else if (count == 3) {
    Emit(q[2], far, layer);
  }
  EndPrimitive();
}
