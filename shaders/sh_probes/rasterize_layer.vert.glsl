#version 450 core
#extension GL_ARB_shader_viewport_layer_array : require
// rasterize_cubemaps without a geometry shader: instance 6 p + f projects
// the scene onto face f of probe p (or of listed probe p of a batch,
// uBatchCount > 0) and writes gl_Layer itself; clip distances keep each
// triangle inside the probe's tile, and the clipper drops the triangles a
// face cannot see. Same output as rasterize.geom.glsl.
#include "common/scene.glsl"
#include "sh_probes/sh.glsl"
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
layout(std430, binding = 10) readonly buffer BatchProbes { int batch_probes[]; };
uniform int uBatchCount;
uniform vec3 uGridOrigin;
uniform vec3 uGridSpacing;
uniform ivec3 uGridDims;
uniform int uAtlasTiles;
uniform ivec2 uAtlasTileCount;  // tiles across, down
uniform float uNear;
uniform float uFar;
out vec3 gWorld;
out vec3 gNormal;
out vec2 gUv;
flat out vec3 gProbe;
out float gl_ClipDistance[4];
void main() {
  int slot = gl_InstanceID / 6, face = gl_InstanceID % 6;
  int probe = uBatchCount > 0 ? batch_probes[slot] : slot;
  ivec3 c = ivec3(probe % uGridDims.x, (probe / uGridDims.x) % uGridDims.y,
                  probe / (uGridDims.x * uGridDims.y));
  vec3 center = uGridOrigin + (vec3(c) + 0.5) * uGridSpacing;
  vec3 world = (uModel * vec4(aPosition, 1.0)).xyz;
  vec3 rel = world - center;
  vec3 fwd = FACE_FORWARD[face], up = FACE_UP[face], right = FaceRight(face);
  float w = dot(rel, fwd);
  // 90-degree perspective: ndc = (u, v) of sh.glsl's texel directions.
  vec4 p = vec4(dot(rel, right), dot(rel, up), ((uFar + uNear) * w - 2.0 * uFar * uNear) / (uFar - uNear), w);
  gl_ClipDistance[0] = p.w - p.x;
  gl_ClipDistance[1] = p.w + p.x;
  gl_ClipDistance[2] = p.w - p.y;
  gl_ClipDistance[3] = p.w + p.y;
  // Face ndc [-1, 1] -> this probe's tile of the atlas (linear in x and w,
  // so interpolation stays perspective-correct).
  ivec2 tile = ivec2(probe % uAtlasTiles, probe / uAtlasTiles);
  p.xy = (p.xy + p.w * (1.0 + 2.0 * vec2(tile))) / vec2(uAtlasTileCount) - p.w;
  gl_Position = p;
  gWorld = world;
  gNormal = uNormalMatrix * aNormal;
  gUv = aUv;
  gProbe = center;
  gl_Layer = face;
}
