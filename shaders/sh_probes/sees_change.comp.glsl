#version 450 core
// Which probes' cube maps see a change, and how much of them (sh_probes'
// progressive update): one work group per probe tests each texel's segment
// from the probe to the surface it stored (to infinity where it saw
// nothing) against the box around what moved (old and new place). A probe
// sees the change when a segment crosses the box, or the probe sits in it:
// only then can its cube map's content differ after the move. Its answer
// is the solid angle of those texels (Eq. 2's A(omega)) in micro-steradians,
// the whole sphere when it sits in the box: the share of what it projects
// that may have changed, which orders the probes' re-rendering.
#include "sh_probes/bindings.glsl"
#include "sh_probes/probe_grid.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SH_BINDING_SEES_CHANGE) writeonly buffer SeesChange { int sees_change[]; };
uniform vec3 uBoxMin;
uniform vec3 uBoxMax;
shared int seen_micro_sr;

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
  if (lane == 0) seen_micro_sr = 0;
  barrier();
  ivec3 c = ivec3(probe % uGridDims.x, (probe / uGridDims.x) % uGridDims.y,
                  probe / (uGridDims.x * uGridDims.y));
  vec3 o = ProbePosition(c);
  ivec2 origin = ProbeTile(probe) * uFaceSize;
  int per_face = uFaceSize * uFaceSize;
  const float kMicro = 1e6;
  bool inside = all(greaterThanEqual(o, uBoxMin)) && all(lessThanEqual(o, uBoxMax));
  float seen = 0.0;
  for (int t = lane; t < 6 * per_face && !inside; t += 64) {
    int face = t / per_face;
    ivec2 ij = ivec2((t % per_face) % uFaceSize, (t % per_face) / uFaceSize);
    float dist = texelFetch(uProbeDistance, ivec3(origin + ij, face), 0).r;
    if (SegmentCrossesBox(o, TexelDirection(face, ij, uFaceSize), dist > 0.0 ? dist : 3.4e38)) {
      seen += TexelSolidAngle(ij, uFaceSize);
    }
  }
  // At least 1 for any hit: a sliver of a texel still sees the change.
  if (seen > 0.0) atomicAdd(seen_micro_sr, max(int(seen * kMicro), 1));
  barrier();
  if (lane == 0) sees_change[probe] = inside ? int(4.0 * PI * kMicro) : seen_micro_sr;
}
