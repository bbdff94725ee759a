#version 450 core
// `avg`, illuminate stage (paper Sec. III-C): deferred shading with
// interleaved sampling (Keller & Heidrich 2001). The target is the
// G-buffer split into 4 x 4 tiles, tile (i, j) holding the pixels
// (4x + i, 4y + j), i.e. the swizzle of Segovia et al. fused into this
// pass; every pixel of tile k = i + 4 j is lit by VPLs k, k + 16, ... only,
// so a tile reads the same VPLs and shadow-map layers throughout.
// Writes indirect irradiance (scaled to estimate all VPLs) and, at full
// rate, direct irradiance; the filter stage reassembles and filters.
// Glossy receivers weight each VPL and each light by the BRDF,
// f(v, l) cos_x (common/brdf.glsl; v towards the camera), and write the
// reflected radiance demodulated by a(v) (avg/receiver.glsl).
#include "avg/bindings.glsl"
#include "render/direct_light.glsl"
#include "avg/receiver.glsl"
#include "avg/vpl.glsl"
layout(binding = AVG_UNIT_VPL_SHADOWS) uniform sampler2DArrayShadow uVplShadows;
layout(binding = GS_UNIT_GBUFFER_POSITION) uniform sampler2D uGPosition;
layout(binding = GS_UNIT_GBUFFER_NORMAL) uniform sampler2D uGNormal;
uniform ivec2 uImageSize;
uniform ivec2 uTileSize;  // ceil(image size / 4)
uniform int uVplCount;
uniform float uClamp2;    // d^2, the stated geometry-term bias (params.clamp)
uniform int uVisibility;  // 0: VPLs unshadowed (the paper's NV column)
uniform float uVplTexel;  // texel size of a VPL map at unit distance
layout(location = 0) out vec4 oIndirect;  // rgb irradiance, a: 1 where estimated
layout(location = 1) out vec4 oDirect;

const int kSubsets = 16;

// Visibility of receiver p (normal n) from VPL v; w: unit VPL -> p. Normal
// and slope-scaled receiver offsets as for the cube maps in direct_light.glsl.
float VplVisibility(Vpl v, vec3 p, vec3 n, vec3 w, float dist) {
  float c = max(-dot(n, w), 0.0);
  float slope = 1.0 + 2.0 * sqrt(max(0.0, 1.0 - c * c)) / max(c, 0.4);
  vec3 q = p + n * (dist * uVplTexel) - w * (dist * uVplTexel * slope);
  vec3 local = VplLocal(v, q - v.position_far.xyz);
  float ld = length(local);
  // Offset behind the VPL's plane: grazing (cos_v ~ 0), nothing to test.
  if (local.z <= 0.0 || ld <= 0.0) return 1.0;
  vec2 uv = ParaboloidUv(local / ld) * 0.5 + 0.5;
  return texture(uVplShadows, vec4(uv, v.normal_layer.w, ld / v.position_far.w));
}

void main() {
  ivec2 s = ivec2(gl_FragCoord.xy);
  ivec2 tile = s / uTileSize;
  ivec2 px = (s - tile * uTileSize) * 4 + tile;
  oIndirect = vec4(0.0);
  oDirect = vec4(0.0);
  if (any(greaterThanEqual(tile, ivec2(4))) || any(greaterThanEqual(px, uImageSize))) return;
  vec4 pos = texelFetch(uGPosition, px, 0);
  if (pos.w == 0.0) return;
  vec3 p = pos.xyz;
  vec3 n = texelFetch(uGNormal, px, 0).xyz;
  SurfaceBrdf b = ReceiverBrdf(px);
  bool lambertian = BrdfLambertian(b);
  vec3 view = ReceiverView(p, n);
  // Glossy: pi f(v, l) / a(v) per VPL and light, so that e stays irradiance-like.
  vec3 demodulate = lambertian ? vec3(0.0) : PI / ReceiverAlbedo(b, n, view);

  int k = tile.x + 4 * tile.y;
  int count = max(uVplCount - k + kSubsets - 1, 0) / kSubsets;  // VPLs k, k + 16, ...
  vec3 e = vec3(0.0);
  for (int j = k; j < uVplCount; j += kSubsets) {
    Vpl v = vpls[j];
    vec3 d = p - v.position_far.xyz;
    float r2 = dot(d, d);
    vec3 w = d * inversesqrt(max(r2, 1e-30));
    float cv = dot(v.normal_layer.xyz, w);
    float cx = -dot(n, w);
    if (cv <= 0.0 || cx <= 0.0) continue;
    float vis = uVisibility != 0 ? VplVisibility(v, p, n, w, sqrt(r2)) : 1.0;
    // A Lambertian VPL of flux Phi has intensity Phi / pi cos_v, so with the
    // geometry term G of the paper's Sec. III-C (r^2 biased by d^2):
    // E = Phi / pi * cos_v cos_x / (r^2 + d^2). A glossy receiver reflects
    // L = f(v, -w) E of it towards v (the rendering equation's integrand),
    // its lobe widened to the disk of radius d that the bias stands for
    // (VplGlossyResponse), so a single VPL's highlight is wider than the
    // 4-pixel interleave period the filter reconstructs.
    vec3 ej = v.flux.rgb * (INV_PI * cv * cx * vis / max(r2 + uClamp2, 1e-30));
    // A glossy VPL sends its flux into its BRDF's lobe for the light it
    // received (Keller 1997, Sec. 2: a VPL carries the BRDF of its hit
    // point): intensity Phi f(w_i, w) cos_v / a(w_i) instead of Phi / pi
    // cos_v, the lobe normalised by its directional albedo so the VPL
    // still leaves with its flux, and widened like a receiver's to the
    // disk the bias stands for (VplGlossyResponse, reciprocity: f(w_i, w)
    // = f(w, w_i)).
    SurfaceBrdf vb = VplBrdf(v);
    if (!BrdfLambertian(vb)) {
      ej *= VplGlossyResponse(vb, v.normal_layer.xyz, v.incident_roughness.xyz, w, r2, uClamp2);
    }
    e += lambertian ? ej : ej * VplGlossyResponse(b, n, view, -w, r2, uClamp2);
  }
  // Subset k holds `count` of the uVplCount VPLs: scale to estimate them all.
  float scale = count > 0 ? float(uVplCount) / float(count) : 0.0;
  oIndirect = vec4(FiniteOrZero(e * scale), count > 0 ? 1.0 : 0.0);
  vec3 direct = lambertian ? DirectIrradiance(p, n) : DirectReflected(p, n, view, b) * demodulate;
  oDirect = vec4(FiniteOrZero(direct), 1.0);
}
