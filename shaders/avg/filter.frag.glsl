#version 450 core
// `avg`, filter stage (paper Sec. III-C): reassembles the split image
// (inverse swizzle, fused into this pass) and removes the interleaving
// pattern with a 4 x 4 box filter -- one pixel of each of the 16 subsets --
// that skips neighbours across discontinuities (normals further apart than
// uNormalCos, or points off this pixel's plane or too far away), then
// re-weights; Lambertian and glossy receivers do not mix (their values are
// demodulated differently, avg/receiver.glsl). Finally
// L = a(v) / pi * (E_direct + E_indirect) + emission, a(v) the albedo of a
// Lambertian receiver, the BRDF's directional albedo of a glossy one.
#include "avg/receiver.glsl"
layout(binding = 8) uniform sampler2D uGPosition;
layout(binding = 9) uniform sampler2D uGNormal;
layout(binding = 12) uniform sampler2D uIndirect;  // split layout
layout(binding = 13) uniform sampler2D uDirect;    // split layout
uniform ivec2 uImageSize;
uniform ivec2 uTileSize;
uniform float uPixelAngle;  // 2 tan(yfov / 2) / height: pixel size at unit distance
uniform float uNormalCos;
uniform vec3 uBackground;
out vec4 oRadiance;

ivec2 Split(ivec2 px) { return (px & 3) * uTileSize + (px >> 2); }

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec4 pos = texelFetch(uGPosition, px, 0);
  if (pos.w == 0.0) {
    oRadiance = vec4(uBackground, 1.0);
    return;
  }
  vec3 p = pos.xyz;
  vec3 n = texelFetch(uGNormal, px, 0).xyz;
  vec3 to_eye = uCameraPos - p;
  float eye_dist = length(to_eye);
  float footprint = eye_dist * uPixelAngle;
  float facing = max(abs(dot(n, to_eye)) / max(eye_dist, 1e-30), 0.1);
  // The window spans 3 pixels: on this surface that is 3 footprints / cos.
  float max_dist = 4.0 * footprint / facing;
  float max_plane = 2.0 * footprint;
  SurfaceBrdf b = ReceiverBrdf(px);
  bool lambertian = BrdfLambertian(b);

  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int dy = -2; dy <= 1; ++dy) {
    for (int dx = -2; dx <= 1; ++dx) {
      ivec2 q = px + ivec2(dx, dy);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, uImageSize))) continue;
      vec4 qp = texelFetch(uGPosition, q, 0);
      if (qp.w == 0.0) continue;
      vec3 diff = qp.xyz - p;
      if (dot(n, texelFetch(uGNormal, q, 0).xyz) < uNormalCos) continue;
      if (abs(dot(diff, n)) > max_plane || length(diff) > max_dist) continue;
      if (BrdfLambertian(ReceiverBrdf(q)) != lambertian) continue;
      vec4 e = texelFetch(uIndirect, Split(q), 0);
      sum += e.rgb * e.a;
      weight += e.a;
    }
  }
  vec3 indirect = weight > 0.0 ? sum / weight : vec3(0.0);
  vec3 direct = texelFetch(uDirect, Split(px), 0).rgb;
  vec3 albedo = ReceiverAlbedo(b, n, ReceiverView(p, n));
  vec3 emission = texelFetch(uGEmission, px, 0).rgb;
  oRadiance = vec4(FiniteOrZero(albedo * INV_PI * (direct + indirect) + emission), 1.0);
}
