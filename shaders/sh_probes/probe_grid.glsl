// The probe grid: positions, the atlas that holds every probe's six faces,
// SH coefficients, and irradiance at a surface point by (visibility-)
// weighted trilinear interpolation (Nijasure et al. 2005, Sections 3.3, 6).
#include "sh_probes/bindings.glsl"
#include "sh_probes/sh.glsl"

uniform vec3 uGridOrigin;   // scene bounds min
uniform vec3 uGridSpacing;  // cell size; probes sit at cell centres
uniform ivec3 uGridDims;
uniform int uFaceSize;
uniform int uAtlasTiles;    // tiles per atlas row
uniform int uCoefficients;  // bands^2
uniform int uIndirectShadows;

// Coefficient k of probe p at coefficients[k * probes + p] (rgb).
layout(std430, binding = SH_BINDING_COEFFICIENTS) readonly buffer ShCoefficients { vec4 coefficients[]; };
// 1 for a probe that sees the scene, 0 for one inside geometry.
layout(std430, binding = SH_BINDING_VALID) readonly buffer ProbeValid { float probe_valid[]; };
layout(binding = SH_UNIT_DISTANCE) uniform sampler2DArray uProbeDistance;  // 0: nothing hit

int ProbeCount() { return uGridDims.x * uGridDims.y * uGridDims.z; }
int ProbeIndex(ivec3 c) { return c.x + uGridDims.x * (c.y + uGridDims.y * c.z); }
vec3 ProbePosition(ivec3 c) { return uGridOrigin + (vec3(c) + 0.5) * uGridSpacing; }
ivec2 ProbeTile(int probe) { return ivec2(probe % uAtlasTiles, probe / uAtlasTiles); }

vec3 ProbeIrradiance(int probe, vec3 n) {
  float y[SH_MAX];
  ShBasis(n, y);
  int count = ProbeCount();
  vec3 e = vec3(0.0);
  for (int k = 0; k < uCoefficients; ++k) {
    e += LambertFactor(k) * y[k] * coefficients[k * count + probe].rgb;
  }
  return e;
}

// Section 6 on the GPU: is `x` (already lifted off its surface) visible from
// probe `c`? Soft test: 1 up to the distance the probe's depth cube stores
// in that direction, falling linearly to 0 over `ramp` beyond it.
float ProbeVisibility(ivec3 c, int probe, vec3 x, float ramp) {
  vec3 d = x - ProbePosition(c);
  float dist = length(d);
  if (dist < 1e-30) return 1.0;
  int face;
  ivec2 ij;
  DirectionToTexel(d / dist, uFaceSize, face, ij);
  float stored = texelFetch(uProbeDistance, ivec3(ProbeTile(probe) * uFaceSize + ij, face), 0).r;
  if (stored <= 0.0) return 1.0;  // the probe saw nothing that way
  return clamp((stored - dist) / ramp + 1.0, 0.0, 1.0);
}

// Irradiance from the grid at surface point p with normal n: trilinear
// weights (Section 3.3), invalid probes dropped, each neighbour weighted by
// its visibility when uIndirectShadows; renormalized by the weight sum.
vec3 GridIrradiance(vec3 p, vec3 n) {
  vec3 g = (p - uGridOrigin) / uGridSpacing - 0.5;
  ivec3 hi = max(uGridDims - 1, ivec3(0));
  ivec3 base = clamp(ivec3(floor(g)), ivec3(0), max(uGridDims - 2, ivec3(0)));
  vec3 t = clamp(g - vec3(base), 0.0, 1.0);
  float s = min(uGridSpacing.x, min(uGridSpacing.y, uGridSpacing.z));
  vec3 x = p + n * (0.3 * s);  // normal offset: test a point off the surface
  vec3 sum = vec3(0.0), plain = vec3(0.0);
  float wsum = 0.0, plain_wsum = 0.0;
  for (int i = 0; i < 8; ++i) {
    ivec3 o = ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    ivec3 c = min(base + o, hi);
    int probe = ProbeIndex(c);
    vec3 tw = mix(1.0 - t, t, vec3(o));
    float w = tw.x * tw.y * tw.z * probe_valid[probe];
    if (w <= 0.0) continue;
    vec3 e = ProbeIrradiance(probe, n);
    plain += w * e;
    plain_wsum += w;
    if (uIndirectShadows != 0) w *= ProbeVisibility(c, probe, x, 0.1 * s);
    sum += w * e;
    wsum += w;
  }
  // No neighbour visible: fall back to the valid ones rather than go black.
  vec3 e = wsum > 1e-6 ? sum / wsum : (plain_wsum > 1e-6 ? plain / plain_wsum : vec3(0.0));
  // Band-limited (l <= 2) irradiance can ring below zero; negative
  // irradiance is not light, so it is cut at zero (docs/ARCHITECTURE.md).
  return max(FiniteOrZero(e), vec3(0.0));
}
