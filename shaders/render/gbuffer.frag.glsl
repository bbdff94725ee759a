#version 450 core
// G-buffer: world position (w = 1 where geometry), shading normal facing the
// viewer, linear albedo, emitted radiance.
#include "bindings.glsl"
#include "common/math.glsl"
#include "common/scene.glsl"
layout(binding = GS_UNIT_BASE_COLOR) uniform sampler2D uBaseColorTex;
layout(binding = GS_UNIT_EMISSIVE) uniform sampler2D uEmissiveTex;
in vec3 vWorld;
in vec3 vNormal;
in vec2 vUv;
layout(location = 0) out vec4 oPosition;
layout(location = 1) out vec4 oNormal;
layout(location = 2) out vec4 oAlbedo;
layout(location = 3) out vec4 oEmission;
void main() {
  Material m = materials[uMaterial];
  vec3 n = SafeNormalize(vNormal, vec3(0.0, 1.0, 0.0));
  // Surfaces are lit on the side the viewer sees.
  if (!gl_FrontFacing) n = -n;
  vec3 albedo = m.base_color.rgb;
  if (m.textures.x >= 0) albedo *= texture(uBaseColorTex, vUv).rgb;
  vec3 emission = m.emission.rgb;
  if (m.textures.y >= 0) emission *= texture(uEmissiveTex, vUv).rgb;
  oPosition = vec4(vWorld, 1.0);
  oNormal = vec4(n, 0.0);
  oAlbedo = vec4(clamp(albedo, 0.0, 1.0), 1.0);
  oEmission = vec4(emission, 0.0);
}
