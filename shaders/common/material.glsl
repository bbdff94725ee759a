// A drawn surface's material as rasterizing passes read it (the view's
// G-buffer, the probes' cube maps): base colour, emission, metallic and
// roughness, each times its texture when it has one (scene/gpu_scene binds
// them per draw).
#include "bindings.glsl"
#include "common/scene.glsl"
layout(binding = GS_UNIT_BASE_COLOR) uniform sampler2D uBaseColorTex;
layout(binding = GS_UNIT_EMISSIVE) uniform sampler2D uEmissiveTex;
layout(binding = GS_UNIT_METALLIC_ROUGHNESS) uniform sampler2D uMetallicRoughnessTex;

// Texture k's coordinates (0 base colour, 1 emissive, 2 metallic-roughness)
// through its KHR_texture_transform.
vec2 TextureUv(Material m, int k, vec2 uv) {
  vec3 h = vec3(uv, 1.0);
  return vec2(dot(m.uv_transform[2 * k].xyz, h), dot(m.uv_transform[2 * k + 1].xyz, h));
}

// Texture k of m at uv, its level of detail from the derivatives of uv
// (the interpolated coordinates) carried through the transform's linear
// part. Implicit derivatives of TextureUv's result gave a high mip level
// along every triangle edge on llvmpipe (the uv's own derivatives were
// right there, printed from this pass; the transform comes from the
// materials buffer, which helper invocations, a quad's pixels outside the
// triangle, seem to read as zeros): a dotted seam down each quad's
// diagonal, TextureTransform.TheSamplerFiltersBetweenTexels.
vec4 MaterialTexture(sampler2D tex, Material m, int k, vec2 uv) {
  vec2 dx = dFdx(uv), dy = dFdy(uv);
  vec2 a = m.uv_transform[2 * k].xy, b = m.uv_transform[2 * k + 1].xy;
  return textureGrad(tex, TextureUv(m, k, uv), vec2(dot(a, dx), dot(b, dx)),
                     vec2(dot(a, dy), dot(b, dy)));
}

// Linear albedo in [0, 1].
vec3 SurfaceAlbedo(Material m, vec2 uv) {
  vec3 albedo = m.base_color.rgb;
  if (m.textures.x >= 0) albedo *= MaterialTexture(uBaseColorTex, m, 0, uv).rgb;
  return clamp(albedo, 0.0, 1.0);
}

// x: metallic, y: roughness, both in [0, 1] (glTF 2.0 3.9.2: the texture's
// B and G channels, linear, times the factors).
vec2 SurfaceMetallicRoughness(Material m, vec2 uv) {
  vec2 mr = m.pbr.xy;
  if (m.textures.w >= 0) mr *= MaterialTexture(uMetallicRoughnessTex, m, 2, uv).bg;
  return clamp(mr, 0.0, 1.0);
}

// Emitted radiance (nits).
vec3 SurfaceEmission(Material m, vec2 uv) {
  vec3 emission = m.emission.rgb;
  if (m.textures.y >= 0) emission *= MaterialTexture(uEmissiveTex, m, 1, uv).rgb;
  return emission;
}
