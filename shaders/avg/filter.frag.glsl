#version 450 core
// `avg`, filter stage (paper Sec. III-C): reassembles the split image
// (inverse swizzle, fused into this pass) and removes the interleaving
// pattern with a 4 x 4 box filter -- one pixel of each of the 16 subsets --
// that skips neighbours across discontinuities (normals further apart than
// uNormalCos, or points off this pixel's plane or too far away), then
// re-weights; Lambertian and glossy receivers do not mix (their values are
// demodulated differently, avg/receiver.glsl). Glossy receivers use the
// box convolved with itself (a 7 x 7 tent, same subset weights): a
// single VPL's highlight reconstructs as a pyramid, not a 4 x 4 block.
// So do Lambertian receivers when a VPL reflects through a glossy lobe
// (uTentEverywhere): its spot on a wall is as narrow as a highlight, and
// the box showed it as 4 x 4 blocks; a scene without glossy VPLs keeps
// the box.
// Finally L = a(v) / pi * (E_direct + E_indirect) + emission, a(v) the
// albedo of a Lambertian receiver, the BRDF's directional albedo of a
// glossy one.
#include "avg/bindings.glsl"
#include "avg/receiver.glsl"
layout(binding = GS_UNIT_GBUFFER_POSITION) uniform sampler2D uGPosition;
layout(binding = GS_UNIT_GBUFFER_NORMAL) uniform sampler2D uGNormal;
layout(binding = AVG_UNIT_SPLIT_INDIRECT) uniform sampler2D uIndirect;  // split layout
layout(binding = AVG_UNIT_SPLIT_DIRECT) uniform sampler2D uDirect;    // split layout
uniform ivec2 uImageSize;
uniform ivec2 uTileSize;
uniform float uPixelAngle;  // 2 tan(yfov / 2) / height: pixel size at unit distance
uniform float uNormalCos;
uniform int uTentEverywhere;  // 1: some VPL is glossy
out vec4 oRadiance;

ivec2 Split(ivec2 px) { return (px & 3) * uTileSize + (px >> 2); }

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec4 pos = texelFetch(uGPosition, px, 0);
  if (pos.w == 0.0) {
    oRadiance = vec4(texelFetch(uGEmission, px, 0).rgb, 1.0);  // the background (render/sky)
    return;
  }
  vec3 p = pos.xyz;
  vec3 n = texelFetch(uGNormal, px, 0).xyz;
  vec3 to_eye = uCameraPos - p;
  float eye_dist = length(to_eye);
  float footprint = eye_dist * uPixelAngle;
  float facing = max(abs(dot(n, to_eye)) / max(eye_dist, 1e-30), 0.1);
  SurfaceBrdf b = ReceiverBrdf(px);
  bool lambertian = BrdfLambertian(b);
  // Lambertian: the 4 x 4 box, offsets -2..+1. Glossy: the box convolved
  // with itself, a 7 x 7 tent of weights (4 - |dx|)(4 - |dy|), offsets
  // -3..+3. Every residue mod 4 gets weight 4 per axis (0: 4; 1: 3 + 1;
  // 2: 2 + 2; 3: 1 + 3), so each of the 16 subsets still counts 16 / 256
  // on a flat face and the pattern cancels as with the box, but a value
  // that only one subset holds (a single VPL's highlight) spreads as a
  // continuous pyramid instead of a 4 x 4 block with hard edges.
  bool box = lambertian && uTentEverywhere == 0;
  int lo = box ? -2 : -3, hi = box ? 1 : 3;
  // The window spans hi - lo pixels: on this surface that many footprints
  // / cos (4 for the box's 3, as before; 7 for the tent's 6).
  float max_dist = float(hi - lo + 1) * footprint / facing;
  float max_plane = 2.0 * footprint;

  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int dy = lo; dy <= hi; ++dy) {
    for (int dx = lo; dx <= hi; ++dx) {
      ivec2 q = px + ivec2(dx, dy);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, uImageSize))) continue;
      vec4 qp = texelFetch(uGPosition, q, 0);
      if (qp.w == 0.0) continue;
      vec3 diff = qp.xyz - p;
      if (dot(n, texelFetch(uGNormal, q, 0).xyz) < uNormalCos) continue;
      if (abs(dot(diff, n)) > max_plane || length(diff) > max_dist) continue;
      if (BrdfLambertian(ReceiverBrdf(q)) != lambertian) continue;
      vec4 e = texelFetch(uIndirect, Split(q), 0);
      float w = box ? e.a : e.a * float((4 - abs(dx)) * (4 - abs(dy)));
      sum += e.rgb * w;
      weight += w;
    }
  }
  vec3 indirect = weight > 0.0 ? sum / weight : vec3(0.0);
  vec3 direct = texelFetch(uDirect, Split(px), 0).rgb;
  vec3 albedo = ReceiverAlbedo(b, n, ReceiverView(p, n));
  vec3 emission = texelFetch(uGEmission, px, 0).rgb;
  oRadiance = vec4(FiniteOrZero(albedo * INV_PI * (direct + indirect) + emission), 1.0);
}
