#version 450 core
// render_cubemaps: shade every stored probe texel with direct light (the
// same shadow maps as `direct`) plus the current indirect estimate:
// L = albedo / pi * (E_direct + E_indirect) (Section 3, step 2). Emission
// is not stored: the probes carry reflected light only, since emitters
// already light surfaces through the direct term.
#include "sh_probes/bindings.glsl"
#include "render/direct_light.glsl"
#include "sh_probes/texel.glsl"
#include "sh_probes/batch.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = SH_IMAGE_DIRECT, rgba32f) uniform image2DArray uDirect;
layout(binding = SH_IMAGE_INDIRECT, rgba32f) readonly uniform image2DArray uIndirect;
layout(binding = SH_IMAGE_RADIANCE, rgba32f) writeonly uniform image2DArray uRadiance;
uniform int uComputeDirect;  // 1: recompute E_direct (lights or geometry changed)
uniform int uUseIndirect;    // 0 on the first bounce
void main() {
  ivec3 atlas;
  if (!BatchTexel(uFaceSize, uAtlasTiles, atlas)) return;
  if (any(greaterThanEqual(atlas.xy, imageSize(uRadiance).xy))) return;
  ProbeTexel t;
  if (!LoadProbeTexel(atlas, t)) return;
  vec3 l = vec3(0.0);
  if (t.hit) {
    vec3 e_direct;
    if (uComputeDirect != 0) {
      e_direct = FiniteOrZero(DirectIrradiance(t.position, t.normal));
      imageStore(uDirect, atlas, vec4(e_direct, 0.0));
    } else {
      e_direct = imageLoad(uDirect, atlas).rgb;
    }
    vec3 e = e_direct;
    if (uUseIndirect != 0) e += imageLoad(uIndirect, atlas).rgb;
    l = t.albedo * INV_PI * e;
  }
  imageStore(uRadiance, atlas, vec4(l, 0.0));
}
