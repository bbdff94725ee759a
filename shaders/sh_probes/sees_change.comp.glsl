#version 450 core
// Which probes' cube maps see a change (sh_probes' progressive update): one
// work group per probe tests each texel's segment from the probe to the
// surface it stored (to infinity where it saw nothing) against the box
// around what moved (old and new place). A probe sees the change when a
// segment crosses the box, or the probe sits in it: only then can its cube
// map's content differ after the move.
#include "sh_probes/bindings.glsl"
#include "sh_probes/probe_grid.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SH_BINDING_SEES_CHANGE) writeonly buffer SeesChange { int sees_change[]; };
uniform vec3 uBoxMin;
uniform vec3 uBoxMax;
shared int any_hit;

bool SegmentCrossesBox(vec3 o, vec3 d, float t_max) {
  vec3 inv = 1.0 / d;  // +-inf on an axis-parallel direction: the slab test still holds
  vec3 t0 = (uBoxMin - o) * inv, t1 = (uBoxMax - o) * inv;
  vec3 lo = min(t0, t1), hi = max(t0, t1);
  float enter = max(max(lo.x, lo.y), max(lo.z, 0.0));
  float leave = min(min(hi.x, hi.y), min(hi.z, t_max));
  return enter <= leave;
}

void main() {
  int probe = int(gl_WorkGroupID.x);
  int lane = int(gl_LocalInvocationIndex);
  if (lane == 0) any_hit = 0;
  barrier();
  ivec3 c = ivec3(probe % uGridDims.x, (probe / uGridDims.x) % uGridDims.y,
                  probe / (uGridDims.x * uGridDims.y));
  vec3 o = ProbePosition(c);
  ivec2 origin = ProbeTile(probe) * uFaceSize;
  int per_face = uFaceSize * uFaceSize;
  bool hit = all(greaterThanEqual(o, uBoxMin)) && all(lessThanEqual(o, uBoxMax));
  for (int t = lane; t < 6 * per_face && !hit; t += 64) {
    int face = t / per_face;
    ivec2 ij = ivec2((t % per_face) % uFaceSize, (t % per_face) / uFaceSize);
    float dist = texelFetch(uProbeDistance, ivec3(origin + ij, face), 0).r;
    hit = SegmentCrossesBox(o, TexelDirection(face, ij, uFaceSize), dist > 0.0 ? dist : 3.4e38);
  }
  if (hit) atomicOr(any_hit, 1);
  barrier();
  if (lane == 0) sees_change[probe] = any_hit;
}
