// A batch of probes (sh_probes' progressive update): with uBatchCount > 0
// a texel dispatch covers only the listed probes, work group z = face +
// 6 x (index in the list), x and y within the face; with 0 it covers the
// whole atlas (x, y, z = atlas texel and layer).
#include "sh_probes/bindings.glsl"
layout(std430, binding = SH_BINDING_BATCH) readonly buffer BatchProbes { int batch_probes[]; };
uniform int uBatchCount;

// The atlas texel of this invocation; false when it lies outside the
// listed probe's face (the whole-atlas case is bounds-checked by its
// caller, as before).
bool BatchTexel(int face_size, int atlas_tiles, out ivec3 atlas) {
  ivec3 id = ivec3(gl_GlobalInvocationID);
  if (uBatchCount <= 0) {
    atlas = id;
    return true;
  }
  atlas = ivec3(0);
  int slot = id.z / 6;
  if (slot >= uBatchCount || any(greaterThanEqual(id.xy, ivec2(face_size)))) return false;
  int probe = batch_probes[slot];
  atlas = ivec3(ivec2(probe % atlas_tiles, probe / atlas_tiles) * face_size + id.xy, id.z % 6);
  return true;
}
