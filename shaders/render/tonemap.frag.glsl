#version 450 core
// Linear HDR radiance -> 8-bit display: exposure, filmic curve (Narkowicz's
// ACES fit), sRGB transfer function.
#include "bindings.glsl"
#include "common/math.glsl"
layout(binding = GS_UNIT_HDR) uniform sampler2D uHdr;
uniform float uExposureScale;  // 2^EV
// Pixels whose solver output is NaN or Inf: the engine refuses to encode a
// frame with any (checked on the exponent bits, which no fast-math
// compilation can fold away).
layout(std430, binding = GS_BINDING_NON_FINITE) buffer NonFinite { uint uNonFinite; };
in vec2 vUv;
out vec4 oColor;

vec3 FilmicAces(vec3 x) {
  const float a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
  return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

vec3 LinearToSrgb(vec3 c) {
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  // This pixel's own texel: a filtered fetch would spread a neighbour's
  // NaN (0 x Inf) and count it again.
  const uvec3 exponent = floatBitsToUint(texelFetch(uHdr, ivec2(gl_FragCoord.xy), 0).rgb) &
                         0x7f800000u;
  if (any(equal(exponent, uvec3(0x7f800000u)))) atomicAdd(uNonFinite, 1u);
  vec3 hdr = FiniteOrZero(texture(uHdr, vUv).rgb) * uExposureScale;
  oColor = vec4(LinearToSrgb(FilmicAces(max(hdr, vec3(0.0)))), 1.0);
}
