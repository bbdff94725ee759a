#version 450 core
// interpolate: the indirect irradiance at every probe texel's surface point
// from the current coefficients (Section 3.3, "replace the previous
// L_indirect"), read by the next bounce's render_cubemaps.
#include "sh_probes/bindings.glsl"
#include "sh_probes/texel.glsl"
#include "sh_probes/batch.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = SH_IMAGE_INDIRECT, rgba32f) writeonly uniform image2DArray uIndirect;
void main() {
  ivec3 atlas;
  if (!BatchTexel(uFaceSize, uAtlasTiles, atlas)) return;
  if (any(greaterThanEqual(atlas.xy, imageSize(uIndirect).xy))) return;
  ProbeTexel t;
  if (!LoadProbeTexel(atlas, t)) return;
  vec3 e = t.hit ? GridIrradiance(t.position, t.normal) : vec3(0.0);
  imageStore(uIndirect, atlas, vec4(e, 0.0));
}
