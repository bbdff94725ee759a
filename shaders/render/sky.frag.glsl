#version 450 core
// The G-buffer's background: where no geometry covers a pixel, the
// environment's radiance along the pixel's ray, exactly as pathtrace's
// camera rays see it (solvers/shading/env_light.cpp, Locate: the nearest
// texel of the equirectangular map, rotated about +Y), times the
// intensity. Written as the background's emission with position w = 0, so
// every solver's final pass shows it (render/shade_surface.glsl).
#include "bindings.glsl"
#include "common/math.glsl"
layout(binding = GS_UNIT_ENVIRONMENT) uniform sampler2D uEnvironment;
// The film at distance 1 (render/camera.h, RayDirection): ndc x right,
// ndc y up, and forward; the refinement's sub-pixel jitter in pixels.
uniform vec3 uRight;
uniform vec3 uUp;
uniform vec3 uForward;
uniform vec2 uJitter;
uniform vec2 uSize;
uniform float uRotation;
uniform float uIntensity;
layout(location = 0) out vec4 oPosition;
layout(location = 1) out vec4 oNormal;
layout(location = 2) out vec4 oAlbedo;
layout(location = 3) out vec4 oEmission;
layout(location = 4) out vec4 oSpecular;
void main() {
  // Projection() shifts the image by +jitter: this pixel centre shows the
  // film point jitter pixels before it.
  vec2 ndc = (gl_FragCoord.xy - uJitter) / uSize * 2.0 - 1.0;
  vec3 dir = SafeNormalize(uForward + ndc.x * uRight + ndc.y * uUp, uForward);
  ivec2 size = textureSize(uEnvironment, 0);
  float u = (atan(dir.x, -dir.z) - uRotation) / (2.0 * PI);
  u -= floor(u);
  float theta = acos(clamp(dir.y, -1.0, 1.0));
  ivec2 texel = clamp(ivec2(int(u * float(size.x)), int(theta / PI * float(size.y))), ivec2(0),
                      size - 1);
  oPosition = vec4(dir, 0.0);
  oNormal = vec4(0.0);
  oAlbedo = vec4(0.0);
  oSpecular = vec4(0.0);
  oEmission = vec4(FiniteOrZero(texelFetch(uEnvironment, texel, 0).rgb * uIntensity), 0.0);
}
