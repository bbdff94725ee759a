#version 450 core
// The picture a refining view shows after a change (render/refinement.h):
// the mean of its n new samples, with the picture shown before the change
// (the history) at weight m. The history is clipped to the colours of the
// mean's 3x3 neighbourhood, so what the change made brighter, darker or
// another colour does not linger (temporal anti-aliasing's neighbourhood
// clip), and is not used at all within the screen box of what moved.
// Carried anti-aliasing (uCarry): the history target holds the new
// pixel-centre sample P instead, and the picture at weight m is
// H = P + k (R - C), the last complete picture's mean R less its centre
// sample C, scaled by k = P / C, the lighting's change where the centre
// looks (1 where C is dark against R - C, at most 4), clipped likewise;
// not used where the surface seen at a pixel centre of the 3x3
// neighbourhood changed (its distance, in the centres' alpha, differs):
// what moved, in its old place and its new. Where those centres see the
// same light within 2 %, H is shown whole: nothing there changed but by k.
// Reprojection (uReproject): after a camera move the picture at weight m
// is the one shown before it, at the point where the previous camera saw
// this pixel's surface (bilinear over the four texels around it that saw
// that surface at its distance, within 2 %: not what the move uncovered),
// clipped likewise: temporal anti-aliasing across camera moves.
#include "bindings.glsl"
layout(binding = GS_UNIT_REFINE_MEAN) uniform sampler2D uMean;
layout(binding = GS_UNIT_REFINE_HISTORY) uniform sampler2D uHistory;
layout(binding = GS_UNIT_CARRY_MEAN) uniform sampler2D uCarryMean;
layout(binding = GS_UNIT_CARRY_CENTRE) uniform sampler2D uCarryCentre;
layout(binding = GS_UNIT_REPROJECT_PREVIOUS) uniform sampler2D uPrevious;  // a: eye distance
uniform float uSamples;        // n >= 1
uniform float uHistoryWeight;  // m > 0
uniform int uCarry;            // 1: the history is the carried picture
uniform ivec2 uInvalidMin;     // pixels [min, max) ignore the history
uniform ivec2 uInvalidMax;
uniform int uReproject;  // 1: the history is the previous picture, reprojected
uniform mat4 uPreviousViewProjection;
uniform vec3 uPreviousEye;
uniform mat4 uInverseViewProjection;  // this view's, without jitter
uniform vec3 uEye;
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

// The previous picture where the previous camera saw the surface at pixel
// p: false where it did not (off screen, behind it, uncovered by the move,
// the background).
bool Reprojected(ivec2 p, out vec3 color) {
  color = vec3(0.0);
  // The surface the pixel centre sees, from the distance its centre sample
  // kept (keep_centre.frag.glsl: negative on an emitter, 0 background),
  // not the G-buffer's, which holds the last jittered sample's.
  const float centre = texelFetch(uHistory, p, 0).a;
  if (centre == 0.0) return false;
  const ivec2 size = textureSize(uPrevious, 0);
  const vec2 ndc = (vec2(p) + 0.5) / vec2(size) * 2.0 - 1.0;
  const vec4 near = uInverseViewProjection * vec4(ndc, -1.0, 1.0);
  const vec3 position = uEye + abs(centre) * normalize(near.xyz / near.w - uEye);
  const vec4 clip = uPreviousViewProjection * vec4(position, 1.0);
  if (clip.w <= 0.0) return false;
  const vec2 texel = (clip.xy / clip.w * 0.5 + 0.5) * vec2(size) - 0.5;
  const ivec2 base = ivec2(floor(texel));
  const vec2 f = texel - vec2(base);
  const float expected = sign(centre) * distance(position, uPreviousEye);
  float weight = 0.0;
  for (int j = 0; j <= 1; ++j) {
    for (int i = 0; i <= 1; ++i) {
      const ivec2 q = base + ivec2(i, j);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      const vec4 previous = texelFetch(uPrevious, q, 0);
      if (abs(previous.a - expected) > 0.02 * abs(expected)) continue;
      const float w = (i == 1 ? f.x : 1.0 - f.x) * (j == 1 ? f.y : 1.0 - f.y);
      color += w * previous.rgb;
      weight += w;
    }
  }
  if (weight < 0.25) return false;
  color /= weight;
  return true;
}

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  const vec4 mean = texelFetch(uMean, p, 0);
  const ivec2 last = textureSize(uMean, 0) - 1;
  if (all(greaterThanEqual(p, uInvalidMin)) && all(lessThan(p, uInvalidMax))) {
    oColor = mean;
    return;
  }
  // The history clipped to the box of the mean's 3x3 neighbourhood: its
  // mean +- one standard deviation in YCoCg (variance clipping, Salvi 2016,
  // "An Excursion in Temporal Supersampling"), along the line to the box's
  // centre, so a colour the change took away does not come back at edges.
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
  vec3 kept = texelFetch(uHistory, p, 0).rgb;
  if (uReproject != 0 && !Reprojected(p, kept)) {
    oColor = mean;
    return;
  }
  if (uCarry != 0) {
    // Where the 3x3 neighbourhood's centres see the same surface and the
    // same light within kStill, nothing there changed but by a smooth
    // factor k: the carried picture is the complete one (its sub-pixel
    // samples are at the same offsets as the new ones) and is shown whole,
    // not clipped to nor blended with a prefix of the new samples, whose
    // uneven weights on an edge (an emitter's outline) read worse than
    // either. Elsewhere it is blended in at weight m.
    const float kStill = 0.02;
    bool still = true;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), last);
        const vec4 now = texelFetch(uHistory, q, 0), then = texelFetch(uCarryCentre, q, 0);
        if (abs(now.a - then.a) > 1e-4 * max(abs(now.a), abs(then.a))) {
          oColor = mean;
          return;
        }
        const vec3 change = abs(now.rgb - then.rgb);
        still = still && all(lessThanEqual(change, kStill * max(now.rgb, then.rgb) + 1e-6));
      }
    }
    const vec3 r = texelFetch(uCarryMean, p, 0).rgb, c = texelFetch(uCarryCentre, p, 0).rgb;
    const vec3 added = r - c;
    const vec3 eps = vec3(1e-4) + 0.01 * abs(added);
    const vec3 k = clamp((kept + eps) / (c + eps), vec3(0.0), vec3(4.0));
    kept += k * added;
    if (still) {
      oColor = vec4(kept, mean.a);
      return;
    }
  }
  const vec3 history = FromYCoCg(ClipToBox(ToYCoCg(kept), m1, sigma));
  oColor = vec4((uSamples * mean.rgb + uHistoryWeight * history) / (uSamples + uHistoryWeight),
                mean.a);
}
