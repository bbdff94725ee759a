// Shared constants and guarded helpers: nothing here returns NaN or Inf.
const float PI = 3.14159265358979323846;
const float INV_PI = 0.31830988618379067154;

vec3 SafeNormalize(vec3 v, vec3 fallback) {
  float len2 = dot(v, v);
  return len2 > 1e-30 ? v * inversesqrt(len2) : fallback;
}

float Luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// Replaces NaN/Inf by 0 so a bad texel can never poison a frame. Used only
// at stage boundaries, where a non-finite value would be a bug upstream.
vec3 FiniteOrZero(vec3 v) {
  bvec3 bad = bvec3(isnan(v.x) || isinf(v.x), isnan(v.y) || isinf(v.y), isnan(v.z) || isinf(v.z));
  return mix(v, vec3(0.0), bad);
}
