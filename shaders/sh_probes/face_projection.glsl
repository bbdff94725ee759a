// rasterize_cubemaps' projection of world points onto one face of one
// probe, placed in that probe's tile of the atlas: shared by the layered
// vertex-shader path (rasterize_layer.vert.glsl) and the geometry-shader
// fallback (rasterize.geom.glsl) so the two give the same pixels.
#include "sh_probes/sh.glsl"
uniform vec3 uGridOrigin;
uniform vec3 uGridSpacing;
uniform ivec3 uGridDims;
uniform int uAtlasTiles;
uniform ivec2 uAtlasTileCount;  // tiles across, down
uniform float uNear;
uniform float uFar;

// The centre of probe `probe` (x fastest, then y, then z).
vec3 ProbeCenter(int probe) {
  ivec3 c = ivec3(probe % uGridDims.x, (probe / uGridDims.x) % uGridDims.y,
                  probe / (uGridDims.x * uGridDims.y));
  return uGridOrigin + (vec3(c) + 0.5) * uGridSpacing;
}

// Clip coordinates of `world` on face `face` of the probe at `center`:
// a 90-degree perspective whose ndc (u, v) are sh.glsl's texel directions.
vec4 FaceClip(vec3 world, vec3 center, int face) {
  vec3 rel = world - center;
  float w = dot(rel, FACE_FORWARD[face]);
  return vec4(dot(rel, FaceRight(face)), dot(rel, FACE_UP[face]),
              ((uFar + uNear) * w - 2.0 * uFar * uNear) / (uFar - uNear), w);
}

// Sets the clip distances that keep a face's primitive inside [-w, w]^2
// and moves clip coordinates from face ndc [-1, 1] into probe `probe`'s
// tile of the atlas (linear in x and w: interpolation stays
// perspective-correct).
vec4 IntoTile(vec4 p, int probe) {
  gl_ClipDistance[0] = p.w - p.x;
  gl_ClipDistance[1] = p.w + p.x;
  gl_ClipDistance[2] = p.w - p.y;
  gl_ClipDistance[3] = p.w + p.y;
  ivec2 tile = ivec2(probe % uAtlasTiles, probe / uAtlasTiles);
  p.xy = (p.xy + p.w * (1.0 + 2.0 * vec2(tile))) / vec2(uAtlasTileCount) - p.w;
  return p;
}
