// Direct irradiance from every light, with shadows. Shared by every solver
// that shades with direct light (std430 mirrors of render/direct_lighting.h).
#include "bindings.glsl"
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

// The discs' estimate of E from area samples [first, last): rgb shadowed,
// a: the unshadowed luminance (the visibility ratio's denominator).
vec4 AreaSamplesIrradiance(int first, int last, vec3 p, vec3 n) {
  vec4 e = vec4(0.0);
  for (int i = first; i < last; ++i) {
    AreaSample s = area_samples[i];
    vec3 d = s.position_area.xyz - p;
    float r2 = dot(d, d);
    vec3 wi = d * inversesqrt(max(r2, 1e-30));
    float cx = dot(n, wi);
    float cy = -dot(s.normal_shadow.xyz, wi);
    if (cx <= 0.0 || cy <= 0.0) continue;
    float a = s.position_area.w;
    float v = CubeVisibility(int(s.normal_shadow.w), s.position_area.xyz, s.radiance_far.w, p, n);
    // Point-to-disc form factor F = A cx cy / (pi r^2 + A), so E = pi L F:
    // finite as r -> 0, and the point estimate L A cx cy / r^2 as A -> 0.
    vec3 unshadowed = s.radiance_far.rgb * (a * cx * cy / (r2 + a * INV_PI));
    e += vec4(unshadowed * v, dot(unshadowed, vec3(0.2126, 0.7152, 0.0722)));
  }
  return e;
}

// Irradiance E at p with normal n (W/m^2 in glTF units, i.e. the outgoing
// diffuse radiance is albedo/pi * E).
vec3 DirectIrradiance(vec3 p, vec3 n) {
  vec3 e = vec3(0.0);
  for (int i = 0; i < uPunctualCount; ++i) {
    PunctualLight L = punctual[i];
    int type = int(L.position_type.w);
    if (type == 2) {
      // Directional: illuminance (lux) times cos(theta).
      vec3 wi = -L.direction.xyz;
      float c = dot(n, wi);
      if (c <= 0.0) continue;
      float v = L.cone_shadow.z >= 0.0 ? DirVisibility(int(L.cone_shadow.z), p, n, wi) : 1.0;
      e += L.intensity.rgb * c * v;
      continue;
    }
    vec3 d = L.position_type.xyz - p;
    float r2 = max(dot(d, d), 1e-30);
    vec3 wi = d * inversesqrt(r2);
    float c = dot(n, wi);
    if (c <= 0.0) continue;
    float cone = 1.0;
    if (type == 1) {
      // KHR_lights_punctual spot falloff.
      float cd = dot(L.direction.xyz, -wi);
      cone = clamp(cd * L.cone_shadow.x + L.cone_shadow.y, 0.0, 1.0);
      cone *= cone;
      if (cone <= 0.0) continue;
    }
    float v = L.cone_shadow.z >= 0.0
                  ? CubeVisibility(int(L.cone_shadow.z), L.position_type.xyz, L.cone_shadow.w, p, n)
                  : 1.0;
    // Inverse-square law: E = I cos(theta) / r^2.
    e += L.intensity.rgb * (cone * c * v / r2);
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
