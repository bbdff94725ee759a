#version 450 core
// display: L = L_emitted + albedo / pi * (E_direct + E_indirect). Direct
// light per pixel with the shared shadow maps; the indirect irradiance of
// the leaf elements is interpolated like the paper's splatting (Section
// 4.3): elements near the pixel with a similar normal, weighted by a
// smooth fall-off, re-normalized by the total weight. Glossy pixels take
// the reflected indirect radiance toward the eye from the glossy leaves'
// bins instead (glossy_transfer.h), interpolated between bins and splatted
// the same way; where no glossy leaf is near, albedo(v) / pi x E.
#include "antiradiance/bindings.glsl"
#include "render/shade_surface.glsl"
#include "antiradiance/elements.glsl"
#include "antiradiance/glossy.glsl"
layout(std430, binding = AR_BINDING_GLOSSY_RADIANCE) readonly buffer GlossyRadiance { vec4 glossy_radiance[]; };  // slot x bin
uniform float uBinSpacing;  // sqrt(4 pi / m)
layout(std430, binding = AR_BINDING_GRID) readonly buffer Grid { uint grid[]; };  // cell starts (cells + 1), leaf ids
uniform vec3 uGridMin;
uniform ivec3 uGridDims;
uniform float uGridCell;
uniform float uGridReach;  // the largest splat's radius
in vec2 vUv;
out vec4 oRadiance;

// The grid cells within the largest splat's reach of p (clipped to the
// grid): every splat that can reach p has its centre in one of them.
void CellBlock(vec3 p, out ivec3 lo, out ivec3 hi) {
  lo = clamp(ivec3(floor((p - uGridReach - uGridMin) / uGridCell)), ivec3(0), uGridDims - 1);
  hi = clamp(ivec3(floor((p + uGridReach - uGridMin) / uGridCell)), ivec3(0), uGridDims - 1);
}

// A leaf's splat weight at p (normal n): a smooth fall-off over its
// radius times the normals' agreement; 0 outside it or for normals more
// than ~45 degrees apart.
float SplatWeight(Element e, vec3 p, vec3 n) {
  float nd = dot(n, e.normal.xyz);
  if (nd < 0.7) return 0.0;
  vec3 d = p - e.position_radius.xyz;
  float r2 = e.position_radius.w * e.position_radius.w;
  float t = 1.0 - dot(d, d) / r2;
  if (t <= 0.0) return 0.0;
  return t * t * nd;
}

vec3 IndirectIrradiance(vec3 p, vec3 n) {
  ivec3 lo, hi;
  CellBlock(p, lo, hi);
  int cells = uGridDims.x * uGridDims.y * uGridDims.z;
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        int cell = (z * uGridDims.y + y) * uGridDims.x + x;
        for (uint k = grid[cell]; k < grid[cell + 1]; ++k) {
          Element e = elements[grid[cells + 1 + int(k)]];
          float w = SplatWeight(e, p, n);
          if (w <= 0.0) continue;
          sum += w * e.irradiance.rgb;
          weight += w;
        }
      }
  return weight > 0.0 ? sum / weight : vec3(0.0);
}

// Interpolation between bins toward v: Gaussian weights of standard
// deviation half the bins' spacing over the bins within 1.5 spacings.
const int MAX_TAPS = 16;
int BinTaps(vec3 v, out int bin[MAX_TAPS], out float w[MAX_TAPS]) {
  float cos_support = cos(1.5 * uBinSpacing);
  float inv_two_sigma2 = 2.0 / (uBinSpacing * uBinSpacing);
  int count = 0;
  for (int k = 0; k < uBins && count < MAX_TAPS; ++k) {
    float c = dot(v, bin_direction[k].xyz);
    if (c < cos_support) continue;
    float a = acos(clamp(c, -1.0, 1.0));
    bin[count] = k;
    w[count] = exp(-a * a * inv_two_sigma2);
    ++count;
  }
  return count;
}

// The glossy leaves near p (normal n): their reflected indirect radiance
// toward v, false when none is near.
bool GlossyIndirect(vec3 p, vec3 n, vec3 v, out vec3 l) {
  int bin[MAX_TAPS];
  float bw[MAX_TAPS];
  int taps = BinTaps(v, bin, bw);
  ivec3 lo, hi;
  CellBlock(p, lo, hi);
  int cells = uGridDims.x * uGridDims.y * uGridDims.z;
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        int cell = (z * uGridDims.y + y) * uGridDims.x + x;
        for (uint k = grid[cell]; k < grid[cell + 1]; ++k) {
          Element e = elements[grid[cells + 1 + int(k)]];
          if (e.normal.w < 0.0) continue;  // not glossy
          float w = SplatWeight(e, p, n);
          if (w <= 0.0) continue;
          // This leaf's bins toward v, over the taps above its surface.
          int base = int(e.normal.w) * uBins;
          vec3 lv = vec3(0.0);
          float tw = 0.0;
          for (int i = 0; i < taps; ++i) {
            if (dot(e.normal.xyz, bin_direction[bin[i]].xyz) <= 0.0) continue;
            lv += bw[i] * glossy_radiance[base + bin[i]].rgb;
            tw += bw[i];
          }
          if (tw <= 0.0) continue;
          sum += w * (lv / tw);
          weight += w;
        }
      }
  l = weight > 0.0 ? max(sum / weight, vec3(0.0)) : vec3(0.0);
  return weight > 0.0;
}

void main() {
  GSurface s;
  if (!ReadGBuffer(ivec2(gl_FragCoord.xy), s)) {
    oRadiance = vec4(s.emission, 1.0);  // the background (render/sky)
    return;
  }
  vec3 l_glossy;
  if (!BrdfLambertian(SurfaceBrdfOf(s)) &&
      GlossyIndirect(s.position, s.normal, ViewDirection(s), l_glossy)) {
    oRadiance = vec4(ShadeGlossy(s, l_glossy), 1.0);
    return;
  }
  oRadiance = vec4(ShadeSurface(s, IndirectIrradiance(s.position, s.normal)), 1.0);
}
