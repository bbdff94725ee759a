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
  for (int i = 0; i < uAreaSampleCount; ++i) {
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
    e += s.radiance_far.rgb * (a * cx * cy * v / (r2 + a * INV_PI));
  }
  return e;
}
