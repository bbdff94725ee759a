// Direct irradiance from every light, with shadows, and the radiance a
// glossy BRDF reflects of it. Shared by every solver that shades with
// direct light (std430 mirrors of render/direct_lighting.h).
#include "bindings.glsl"
#include "common/brdf.glsl"
#include "common/math.glsl"

struct PunctualLight {
  vec4 position_type;   // xyz world position, w: 0 point, 1 spot, 2 directional
  vec4 direction;       // xyz: the way the light shines (unit)
  vec4 intensity;       // rgb: colour x intensity (cd, or lux for directional)
  vec4 cone_shadow;     // x: cone scale, y: cone offset, z: shadow index, w: shadow far
};

// One stratified sample of an emissive surface: an oriented disc of area A.
struct AreaSample {
  vec4 position_area;   // xyz world position, w: area A_i = 1 / (N pdf)
  vec4 normal_shadow;   // xyz emitter normal, w: cube index
  vec4 radiance_far;    // rgb emitted radiance, w: shadow far
};

layout(std430, binding = GS_BINDING_PUNCTUAL_LIGHTS) readonly buffer PunctualLights { PunctualLight punctual[]; };
layout(std430, binding = GS_BINDING_AREA_SAMPLES) readonly buffer AreaSamples { AreaSample area_samples[]; };
layout(std430, binding = GS_BINDING_DIR_SHADOW_MATRICES) readonly buffer DirShadowMatrices { mat4 dir_view_proj[]; };

// A uniformly emitting convex polygon (render/emitter_polygons.h) and the
// range of area samples on it.
struct EmitterPolygon {
  vec4 radiance_count;  // rgb emitted radiance, w: vertex count
  vec4 normal;          // xyz: the emitting side
  ivec4 samples;        // x: first area sample, y: how many
  vec4 vertices[8];
};
layout(std430, binding = GS_BINDING_EMITTER_POLYGONS) readonly buffer EmitterPolygons { EmitterPolygon polygons[]; };
uniform int uPolygonCount;  // 0: the discs' estimate alone

layout(binding = GS_UNIT_CUBE_SHADOWS) uniform samplerCubeArrayShadow uCubeShadows;
layout(binding = GS_UNIT_DIR_SHADOWS) uniform sampler2DArrayShadow uDirShadows;
uniform int uPunctualCount;
uniform int uAreaSampleCount;
uniform float uShadowTexel;  // 2 / shadow resolution (texel size at unit distance)

// Visibility of `p` (normal n) from a cube-map shadow caster at `light`.
// Receiver offset along the normal, scaled with distance and texel size,
// keeps the bias scale-invariant (mm to km scenes).
float CubeVisibility(int cube, vec3 light, float far, vec3 p, vec3 n) {
  vec3 d = p - light;
  float dist = length(d);
  vec3 l = d / max(dist, 1e-30);
  float slope = 1.0 + 2.0 * sqrt(max(0.0, 1.0 - dot(n, -l) * dot(n, -l))) / max(abs(dot(n, -l)), 0.2);
  vec3 q = p + n * (dist * uShadowTexel * 1.5) - l * (dist * uShadowTexel * slope);
  vec3 dq = q - light;
  return texture(uCubeShadows, vec4(dq, float(cube)), length(dq) / far);
}

float DirVisibility(int index, vec3 p, vec3 n, vec3 dir) {
  vec4 c = dir_view_proj[index] * vec4(p, 1.0);
  vec3 uvz = c.xyz * 0.5 + 0.5;
  if (any(lessThan(uvz.xy, vec2(0.0))) || any(greaterThan(uvz.xy, vec2(1.0)))) return 1.0;
  float bias = uShadowTexel * (1.0 + 2.0 * (1.0 - abs(dot(n, dir))));
  return texture(uDirShadows, vec4(uvz.xy, float(index), uvz.z - bias));
}

// Unoccluded irradiance factor E / L at p (normal n) from polygon `k`:
// Lambert's formula E = L/2 sum_j Theta_j (n . Gamma_j) (Arvo 1995, eq. 9)
// over the polygon clipped to p's upper hemisphere; 0 unless p is on the
// emitting side (and not in the emitter's own plane).
float PolygonIrradianceFactor(int k, vec3 p, vec3 n) {
  EmitterPolygon poly = polygons[k];
  int count = int(poly.radiance_count.w);
  vec3 e0 = poly.vertices[0].xyz, e1 = poly.vertices[1].xyz, e2 = poly.vertices[2].xyz;
  float size = length(e1 - e0) + length(e2 - e1);
  if (dot(p - e0, poly.normal.xyz) <= 1e-5 * size) return 0.0;
  // Sutherland-Hodgman against the plane dot(q - p, n) >= 0, relative to p.
  vec3 clipped[9];
  int m = 0;
  vec3 prev = poly.vertices[count - 1].xyz - p;
  float dprev = dot(prev, n);
  for (int j = 0; j < count; ++j) {
    vec3 cur = poly.vertices[j].xyz - p;
    float dcur = dot(cur, n);
    if ((dprev >= 0.0) != (dcur >= 0.0)) {
      clipped[m++] = prev + (cur - prev) * (dprev / (dprev - dcur));
    }
    if (dcur >= 0.0) clipped[m++] = cur;
    prev = cur;
    dprev = dcur;
  }
  if (m < 3) return 0.0;
  float sum = 0.0;
  vec3 a = normalize(clipped[m - 1]);
  for (int j = 0; j < m; ++j) {
    vec3 b = normalize(clipped[j]);
    vec3 c = cross(a, b);
    float s = length(c);
    // Theta_j (n . Gamma_j) with Gamma_j = c / |c| and Theta_j the angle
    // between a and b: (angle / sin) (n . c), -> n . c as the edge shrinks.
    float angle = atan(s, dot(a, b));
    sum += (s > 1e-12 ? angle / s : 1.0) * dot(n, c);
    a = b;
  }
  return 0.5 * abs(sum);
}

// Unshadowed irradiance at p (normal n) from area sample i, the direction
// wi towards it; 0 when either side faces away.
vec3 AreaSampleIrradiance(int i, vec3 p, vec3 n, out vec3 wi) {
  AreaSample s = area_samples[i];
  vec3 d = s.position_area.xyz - p;
  float r2 = dot(d, d);
  wi = d * inversesqrt(max(r2, 1e-30));
  float cx = dot(n, wi);
  float cy = -dot(s.normal_shadow.xyz, wi);
  if (cx <= 0.0 || cy <= 0.0) return vec3(0.0);
  float a = s.position_area.w;
  // Point-to-disc form factor F = A cx cy / (pi r^2 + A), so E = pi L F:
  // finite as r -> 0, and the point estimate L A cx cy / r^2 as A -> 0.
  return s.radiance_far.rgb * (a * cx * cy / (r2 + a * INV_PI));
}

float AreaSampleVisibility(int i, vec3 p, vec3 n) {
  AreaSample s = area_samples[i];
  return CubeVisibility(int(s.normal_shadow.w), s.position_area.xyz, s.radiance_far.w, p, n);
}

// The discs' estimate of E from area samples [first, last): rgb shadowed,
// a: the unshadowed luminance (the visibility ratio's denominator).
vec4 AreaSamplesIrradiance(int first, int last, vec3 p, vec3 n) {
  vec4 e = vec4(0.0);
  for (int i = first; i < last; ++i) {
    vec3 wi;
    vec3 unshadowed = AreaSampleIrradiance(i, p, n, wi);
    if (unshadowed == vec3(0.0)) continue;
    float v = AreaSampleVisibility(i, p, n);
    e += vec4(unshadowed * v, Luminance(unshadowed));
  }
  return e;
}

// Irradiance at p (normal n) from punctual light i, unshadowed, and the
// direction wi towards it; 0 when the light is behind or outside its cone.
vec3 PunctualIrradiance(int i, vec3 p, vec3 n, out vec3 wi) {
  PunctualLight L = punctual[i];
  int type = int(L.position_type.w);
  if (type == 2) {
    // Directional: illuminance (lux) times cos(theta).
    wi = -L.direction.xyz;
    float c = dot(n, wi);
    return c <= 0.0 ? vec3(0.0) : L.intensity.rgb * c;
  }
  vec3 d = L.position_type.xyz - p;
  float r2 = max(dot(d, d), 1e-30);
  wi = d * inversesqrt(r2);
  float c = dot(n, wi);
  if (c <= 0.0) return vec3(0.0);
  float cone = 1.0;
  if (type == 1) {
    // KHR_lights_punctual spot falloff.
    float cd = dot(L.direction.xyz, -wi);
    cone = clamp(cd * L.cone_shadow.x + L.cone_shadow.y, 0.0, 1.0);
    cone *= cone;
  }
  // Inverse-square law: E = I cos(theta) / r^2.
  return L.intensity.rgb * (cone * c / r2);
}

// Shadow-map visibility of p (normal n) from punctual light i towards wi.
float PunctualVisibility(int i, vec3 p, vec3 n, vec3 wi) {
  PunctualLight L = punctual[i];
  if (L.cone_shadow.z < 0.0) return 1.0;
  if (int(L.position_type.w) == 2) return DirVisibility(int(L.cone_shadow.z), p, n, wi);
  return CubeVisibility(int(L.cone_shadow.z), L.position_type.xyz, L.cone_shadow.w, p, n);
}

// Irradiance E at p with normal n (W/m^2 in glTF units, i.e. the outgoing
// diffuse radiance is albedo/pi * E).
vec3 DirectIrradiance(vec3 p, vec3 n) {
  vec3 e = vec3(0.0);
  for (int i = 0; i < uPunctualCount; ++i) {
    vec3 wi;
    vec3 ei = PunctualIrradiance(i, p, n, wi);
    if (ei == vec3(0.0)) continue;
    e += ei * PunctualVisibility(i, p, n, wi);
  }
  if (uPolygonCount == 0) return e + AreaSamplesIrradiance(0, uAreaSampleCount, p, n).rgb;
  // Exact unoccluded polygons times their samples' visibility ratio
  // (Heitz et al. 2018, eq. 3): sum(E_disc V) / sum(E_disc), which is 1
  // when nothing occludes, so only shadows depend on the samples. A
  // polygon without a sample in view takes the ratio of those before it.
  vec2 seen = vec2(0.0);
  for (int k = 0; k < uPolygonCount; ++k) {
    float f = PolygonIrradianceFactor(k, p, n);
    if (f <= 0.0) continue;
    ivec4 range = polygons[k].samples;
    vec4 s = AreaSamplesIrradiance(range.x, range.x + range.y, p, n);
    float lum = dot(s.rgb, vec3(0.2126, 0.7152, 0.0722));
    seen += vec2(lum, s.a);
    float visible = s.a > 0.0 ? lum / s.a : (seen.y > 0.0 ? seen.x / seen.y : 1.0);
    e += polygons[k].radiance_count.rgb * (f * clamp(visible, 0.0, 1.0));
  }
  return e;
}

// The solid angle area sample i's disc subtends at p (its finite form
// factor's, as AreaSampleIrradiance: A cos_y / (r^2 + A / pi)).
float AreaSampleSolidAngle(int i, vec3 p) {
  AreaSample s = area_samples[i];
  vec3 d = s.position_area.xyz - p;
  float r2 = dot(d, d);
  float cy = max(-dot(s.normal_shadow.xyz, d * inversesqrt(max(r2, 1e-30))), 0.0);
  float a = s.position_area.w;
  return a * cy / (r2 + a * INV_PI);
}

// f(v, l) for the light of an area sample that subtends solid angle
// `omega` around l: the GGX lobe widened to the sample's size, so that a
// near-mirror lobe, narrower than the samples' spacing, shows the emitter
// as one reflection, not as a spot per sample (issue 29). What the sample
// stands for is the lobe integrated over its disc, i.e. the lobe
// convolved with the disc (as Karis' sphere-light widening, Real Shading
// in UE4, 2013); a GGX of alpha'^2 = alpha^2 + omega / (2 pi) has about
// the half-maximum width of that convolution (a disc of angular radius
// theta, omega = pi theta^2, is a disc of theta / 2 in half-vector space;
// GGX falls to half at tan theta_h = 0.64 alpha: alpha'^2 ~ omega / 5.2).
// D stays normalized, so each sample's reflected power is kept, up to the
// wider lobe's share beyond the emitter's edge. At most 1.
// MirrorAreaLight.DirectShowsTheLampNotItsSamples measured omega / (4 pi)
// (ripples of 26 % between samples), / (2 pi) (12 %) and / pi (5 %, 10 %
// darker: the GGX tails reach past the emitter).
// The BRDF toward the view that DirectReflected applies to each light: an
// includer may define DIRECT_VIEW_BRDF (same arguments as BrdfEval) before
// including this file; render/glossy_bin_direct.comp.glsl averages it over
// a bin's directions, so the lights and shadows are looked up once.
#ifndef DIRECT_VIEW_BRDF
#define DIRECT_VIEW_BRDF BrdfEval
#endif

vec3 BrdfEvalSource(SurfaceBrdf b, vec3 n, vec3 v, vec3 l, float omega) {
  if (BrdfLambertian(b)) return DIRECT_VIEW_BRDF(b, n, v, l);
  float alpha = BrdfAlpha(b);
  float widened = min(alpha * alpha + omega * (0.5 * INV_PI), 1.0);
  SurfaceBrdf w = b;
  w.roughness = sqrt(sqrt(widened));  // BrdfAlpha squares the perceptual roughness
  return DIRECT_VIEW_BRDF(w, n, v, l);
}

// Radiance that BRDF b reflects towards v (unit, from p to the eye) of the
// direct light at p (normal n): each punctual light's and area sample's
// irradiance times f(v, l). Emitter polygons keep their exact unoccluded
// irradiance (as DirectIrradiance) times the BRDF averaged over their
// samples, weighted by each sample's share of that irradiance and its
// visibility: exact for Lambert. Each area sample's lobe is widened to
// the solid angle it stands for (BrdfEvalSource): a lobe narrower than the
// samples' spacing had shown the polygon as spots.
// Lambertian surfaces: baseColor / pi x DirectIrradiance.
vec3 DirectReflected(vec3 p, vec3 n, vec3 v, SurfaceBrdf b) {
  if (BrdfLambertian(b)) return b.base_color * INV_PI * DirectIrradiance(p, n);
  vec3 l = vec3(0.0);
  for (int i = 0; i < uPunctualCount; ++i) {
    vec3 wi;
    vec3 ei = PunctualIrradiance(i, p, n, wi);
    if (ei == vec3(0.0)) continue;
    l += DIRECT_VIEW_BRDF(b, n, v, wi) * ei * PunctualVisibility(i, p, n, wi);
  }
  if (uPolygonCount == 0) {
    for (int i = 0; i < uAreaSampleCount; ++i) {
      vec3 wi;
      vec3 ei = AreaSampleIrradiance(i, p, n, wi);
      if (ei == vec3(0.0)) continue;
      l += BrdfEvalSource(b, n, v, wi, AreaSampleSolidAngle(i, p)) * ei *
           AreaSampleVisibility(i, p, n);
    }
    return l;
  }
  for (int k = 0; k < uPolygonCount; ++k) {
    float f = PolygonIrradianceFactor(k, p, n);
    if (f <= 0.0) continue;
    ivec4 range = polygons[k].samples;
    vec3 weighted = vec3(0.0);  // sum f(v, l_i) V_i E_i / L
    float total = 0.0;          // sum E_i / L (unshadowed)
    for (int i = range.x; i < range.x + range.y; ++i) {
      vec3 wi;
      vec3 ei = AreaSampleIrradiance(i, p, n, wi);
      if (ei == vec3(0.0)) continue;
      float share = Luminance(ei);
      weighted += BrdfEvalSource(b, n, v, wi, AreaSampleSolidAngle(i, p)) *
                  (share * AreaSampleVisibility(i, p, n));
      total += share;
    }
    // No sample in view: the BRDF towards the polygon's first vertex, unshadowed.
    vec3 brdf = total > 0.0 ? weighted / total
                            : DIRECT_VIEW_BRDF(b, n, v, normalize(polygons[k].vertices[0].xyz - p));
    l += polygons[k].radiance_count.rgb * f * brdf;
  }
  return l;
}
