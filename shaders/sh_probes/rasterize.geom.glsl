#version 450 core
// rasterize_cubemaps: every probe's six faces in one pass. Invocation f
// projects the triangle onto face f of probe vProbe and places it in that
// probe's tile of atlas layer f; clip distances keep it inside the tile.
#include "sh_probes/sh.glsl"
layout(triangles, invocations = 6) in;
layout(triangle_strip, max_vertices = 3) out;
uniform vec3 uGridOrigin;
uniform vec3 uGridSpacing;
uniform ivec3 uGridDims;
uniform int uAtlasTiles;
uniform ivec2 uAtlasTileCount;  // tiles across, down
uniform float uNear;
uniform float uFar;
in vec3 vWorld[];
in vec3 vNormal[];
in vec2 vUv[];
flat in int vProbe[];
out vec3 gWorld;
out vec3 gNormal;
out vec2 gUv;
flat out vec3 gProbe;
out float gl_ClipDistance[4];
void main() {
  int face = gl_InvocationID;
  int probe = vProbe[0];
  ivec3 c = ivec3(probe % uGridDims.x, (probe / uGridDims.x) % uGridDims.y,
                  probe / (uGridDims.x * uGridDims.y));
  vec3 center = uGridOrigin + (vec3(c) + 0.5) * uGridSpacing;
  vec3 fwd = FACE_FORWARD[face], up = FACE_UP[face], right = FaceRight(face);
  vec4 clip[3];
  for (int i = 0; i < 3; ++i) {
    vec3 rel = vWorld[i] - center;
    float w = dot(rel, fwd);
    // 90-degree perspective: ndc = (u, v) of sh.glsl's texel directions.
    clip[i] = vec4(dot(rel, right), dot(rel, up), ((uFar + uNear) * w - 2.0 * uFar * uNear) / (uFar - uNear), w);
  }
  // Skip faces the triangle cannot touch (all vertices outside one plane).
  for (int k = 0; k < 2; ++k) {
    if (clip[0][k] > clip[0].w && clip[1][k] > clip[1].w && clip[2][k] > clip[2].w) return;
    if (clip[0][k] < -clip[0].w && clip[1][k] < -clip[1].w && clip[2][k] < -clip[2].w) return;
  }
  if (clip[0].w < uNear && clip[1].w < uNear && clip[2].w < uNear) return;
  ivec2 tile = ivec2(probe % uAtlasTiles, probe / uAtlasTiles);
  vec2 tiles = vec2(uAtlasTileCount);
  for (int i = 0; i < 3; ++i) {
    vec4 p = clip[i];
    gl_ClipDistance[0] = p.w - p.x;
    gl_ClipDistance[1] = p.w + p.x;
    gl_ClipDistance[2] = p.w - p.y;
    gl_ClipDistance[3] = p.w + p.y;
    // Face ndc [-1, 1] -> this probe's tile of the atlas (linear in x and w,
    // so interpolation stays perspective-correct).
    p.xy = (p.xy + p.w * (1.0 + 2.0 * vec2(tile))) / tiles - p.w;
    gl_Position = p;
    gWorld = vWorld[i];
    gNormal = vNormal[i];
    gUv = vUv[i];
    gProbe = center;
    gl_Layer = face;
    EmitVertex();
  }
  EndPrimitive();
}
