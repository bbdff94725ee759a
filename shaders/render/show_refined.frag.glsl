#version 450 core
// The picture a refining view shows after a change (render/refinement.h):
// the mean of its n new samples, with the picture shown before the change
// (the history) at weight m. The history is clipped to the colours of the
// mean's 3x3 neighbourhood, so what the change made brighter, darker or
// another colour does not linger (temporal anti-aliasing's neighbourhood
// clip), and is not used at all within the screen box of what moved.
#include "bindings.glsl"
layout(binding = GS_UNIT_REFINE_MEAN) uniform sampler2D uMean;
layout(binding = GS_UNIT_REFINE_HISTORY) uniform sampler2D uHistory;
uniform float uSamples;        // n >= 1
uniform float uHistoryWeight;  // m > 0
uniform ivec2 uInvalidMin;     // pixels [min, max) ignore the history
uniform ivec2 uInvalidMax;
out vec4 oColor;

vec3 ToYCoCg(vec3 c) {
  return vec3(dot(c, vec3(0.25, 0.5, 0.25)), dot(c, vec3(0.5, 0.0, -0.5)),
              dot(c, vec3(-0.25, 0.5, -0.25)));
}
vec3 FromYCoCg(vec3 c) { return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z); }

// `h` moved towards `centre` until it lies in the box centre +- extent.
vec3 ClipToBox(vec3 h, vec3 centre, vec3 extent) {
  const vec3 d = h - centre;
  const vec3 ratio = abs(d) / max(extent, vec3(1e-7));
  const float m = max(ratio.x, max(ratio.y, ratio.z));
  return m > 1.0 ? centre + d / m : h;
}

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  const vec4 mean = texelFetch(uMean, p, 0);
  if (all(greaterThanEqual(p, uInvalidMin)) && all(lessThan(p, uInvalidMax))) {
    oColor = mean;
    return;
  }
  // The history clipped to the box of the mean's 3x3 neighbourhood: its
  // mean +- one standard deviation in YCoCg (variance clipping, Salvi 2016,
  // "An Excursion in Temporal Supersampling"), along the line to the box's
  // centre, so a colour the change took away does not come back at edges.
  const ivec2 last = textureSize(uMean, 0) - 1;
  vec3 m1 = vec3(0.0), m2 = vec3(0.0);
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const vec3 c = ToYCoCg(texelFetch(uMean, clamp(p + ivec2(dx, dy), ivec2(0), last), 0).rgb);
      m1 += c;
      m2 += c * c;
    }
  }
  m1 /= 9.0;
  const vec3 sigma = sqrt(max(m2 / 9.0 - m1 * m1, vec3(0.0)));
  const vec3 history = FromYCoCg(ClipToBox(ToYCoCg(texelFetch(uHistory, p, 0).rgb), m1, sigma));
  oColor = vec4((uSamples * mean.rgb + uHistoryWeight * history) / (uSamples + uHistoryWeight),
                mean.a);
}
