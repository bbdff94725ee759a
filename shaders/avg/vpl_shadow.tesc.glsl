#version 450 core
// Tessellation of a proxy triangle for its VPL's paraboloid map (issue 19,
// docs/ARCHITECTURE.md "Proxy geometry"). The map is not linear: the
// rasterizer draws edges straight in uv where their true images are arcs
// of radius >= 1 (uv is a stereographic projection), and an arc of
// uv-length s lies within s^2 / 8 of its chord. A piece of length l at
// distance >= r from the VPL subtends <= l / r radians and, in the upper
// hemisphere (uv's derivative is <= 1 there, render/proxy_filters.h),
// spans <= l / r in uv: within half a texel (1 / N) of its chord when
// l / r <= sqrt(8 / N) (uMaxAngle). Each edge is cut into
// ceil(L / (r sqrt(8 / N))) equal pieces, r its nearest distance to the VPL
// (one piece when the whole edge subtends <= sqrt(8 / N)), the inside as
// finely as its finest edge. The primitive generator's per-edge spacing
// depends on that edge's level alone, so neighbours meet vertex for vertex.
#include "avg/vpl.glsl"
layout(vertices = 3) out;
flat in int vVpl[];
flat out int tVpl[];
uniform float uMaxAngle;  // sqrt(8 / N), N the map's resolution

// Pieces for edge a-b; the endpoints are put in one order first, so the two
// triangles sharing the edge compute the same count (no cracks).
float EdgeLevel(vec3 a, vec3 b, vec3 vpl) {
  if (a.x > b.x || (a.x == b.x && (a.y > b.y || (a.y == b.y && a.z > b.z)))) {
    vec3 t = a;
    a = b;
    b = t;
  }
  // A whole edge within the angle needs no cut.
  vec3 da = normalize(a - vpl), db = normalize(b - vpl);
  if (acos(clamp(dot(da, db), -1.0, 1.0)) <= uMaxAngle) return 1.0;
  vec3 e = b - a;
  float len2 = dot(e, e);
  float t = len2 > 0.0 ? clamp(dot(vpl - a, e) / len2, 0.0, 1.0) : 0.0;
  float nearest = length(a + e * t - vpl);
  float pieces = sqrt(len2) / max(nearest * uMaxAngle, 1e-30);
  return clamp(ceil(pieces), 1.0, 64.0);  // GL_MAX_TESS_GEN_LEVEL >= 64
}

void main() {
  gl_out[gl_InvocationID].gl_Position = gl_in[gl_InvocationID].gl_Position;
  tVpl[gl_InvocationID] = vVpl[gl_InvocationID];
  if (gl_InvocationID == 0) {
    Vpl v = vpls[vVpl[0]];
    vec3 vpl = v.position_far.xyz;
    vec3 n = v.normal_layer.xyz;
    vec3 p0 = gl_in[0].gl_Position.xyz, p1 = gl_in[1].gl_Position.xyz,
         p2 = gl_in[2].gl_Position.xyz;
    // Wholly behind the hemisphere: nothing to draw (level 0 drops it).
    if (dot(p0 - vpl, n) < 0.0 && dot(p1 - vpl, n) < 0.0 && dot(p2 - vpl, n) < 0.0) {
      gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = gl_TessLevelOuter[2] = 0.0;
      gl_TessLevelInner[0] = 0.0;
      return;
    }
    // Outer level i is the edge opposite vertex i.
    gl_TessLevelOuter[0] = EdgeLevel(p1, p2, vpl);
    gl_TessLevelOuter[1] = EdgeLevel(p2, p0, vpl);
    gl_TessLevelOuter[2] = EdgeLevel(p0, p1, vpl);
    gl_TessLevelInner[0] =
        max(gl_TessLevelOuter[0], max(gl_TessLevelOuter[1], gl_TessLevelOuter[2]));
  }
}
