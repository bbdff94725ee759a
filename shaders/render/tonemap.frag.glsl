#version 450 core
// Linear HDR radiance -> 8-bit display: exposure, filmic curve (Narkowicz's
// ACES fit), sRGB transfer function.
#include "common/math.glsl"
layout(binding = 0) uniform sampler2D uHdr;
uniform float uExposureScale;  // 2^EV
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
  vec3 hdr = FiniteOrZero(texture(uHdr, vUv).rgb) * uExposureScale;
  oColor = vec4(LinearToSrgb(FilmicAces(max(hdr, vec3(0.0)))), 1.0);
}
