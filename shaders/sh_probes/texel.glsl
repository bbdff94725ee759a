// A texel of the probe atlas: which probe and direction it belongs to, and
// the surface point it saw (shared by render_cubemaps and interpolate).
#include "sh_probes/bindings.glsl"
#include "sh_probes/probe_grid.glsl"
#include "common/brdf.glsl"
#include "common/scene.glsl"
layout(binding = SH_UNIT_NORMAL) uniform sampler2DArray uProbeNormal;  // w: 1 = back face
layout(binding = SH_UNIT_ALBEDO) uniform sampler2DArray uProbeAlbedo;  // a: material index
layout(binding = SH_UNIT_MATERIAL) uniform sampler2DArray uProbeMaterial;  // metallic, roughness

struct ProbeTexel {
  bool hit;
  vec3 probe;  // the probe's position: the eye its cube map was seen from
  vec3 position;
  vec3 normal;
  vec3 albedo;
  vec2 metallic_roughness;
  int material;  // index into the scene's materials; -1 where nothing was hit
};

// False for texels past the last probe's tile.
bool LoadProbeTexel(ivec3 atlas, out ProbeTexel t) {
  ivec2 tile = atlas.xy / uFaceSize;
  int probe = tile.y * uAtlasTiles + tile.x;
  t.hit = false;
  t.probe = t.position = t.normal = t.albedo = vec3(0.0);
  t.metallic_roughness = vec2(0.0, 1.0);
  t.material = -1;
  if (tile.x >= uAtlasTiles || probe >= ProbeCount()) return false;
  float dist = texelFetch(uProbeDistance, atlas, 0).r;
  if (dist <= 0.0) return true;
  ivec3 c = ivec3(probe % uGridDims.x, (probe / uGridDims.x) % uGridDims.y,
                  probe / (uGridDims.x * uGridDims.y));
  vec3 dir = TexelDirection(atlas.z, atlas.xy - tile * uFaceSize, uFaceSize);
  t.hit = true;
  t.probe = ProbePosition(c);
  t.position = t.probe + dir * dist;
  t.normal = texelFetch(uProbeNormal, atlas, 0).xyz;
  vec4 albedo = texelFetch(uProbeAlbedo, atlas, 0);
  t.albedo = albedo.rgb;
  t.material = int(albedo.a);
  t.metallic_roughness = texelFetch(uProbeMaterial, atlas, 0).rg;
  return true;
}

// The surface's BRDF with its material's dielectric F0 and F90 (KHR_materials_ior,
// KHR_materials_specular; the materials are bound by RenderCubemaps).
SurfaceBrdf ProbeTexelBrdf(ProbeTexel t) {
  vec4 specular = t.material >= 0 ? materials[t.material].specular : BRDF_DEFAULT_SPECULAR;
  return SurfaceBrdf(t.albedo, t.metallic_roughness.x, t.metallic_roughness.y, specular);
}
