#version 450 core
// sh_project: one work group per probe sums its six faces' radiance times
// Y_lm times each texel's solid angle (Eq. 2), and marks the probe invalid
// when most of what it sees are back faces (it sits inside geometry).
// With uBatchCount > 0 only the listed probes.
#include "sh_probes/bindings.glsl"
#include "sh_probes/sh.glsl"
layout(local_size_x = 64) in;
layout(binding = SH_IMAGE_RADIANCE, rgba32f) readonly uniform image2DArray uRadiance;
layout(binding = SH_UNIT_NORMAL) uniform sampler2DArray uProbeNormal;
layout(binding = SH_UNIT_DISTANCE) uniform sampler2DArray uProbeDistance;
layout(std430, binding = SH_BINDING_COEFFICIENTS) writeonly buffer ShCoefficients { vec4 coefficients[]; };
layout(std430, binding = SH_BINDING_VALID) writeonly buffer ProbeValid { float probe_valid[]; };
uniform int uFaceSize;
uniform int uAtlasTiles;
uniform int uProbeCount;
uniform int uCoefficients;
// A batch (sh_probes/batch.glsl): work group i projects probe batch_probes[i].
layout(std430, binding = SH_BINDING_BATCH) readonly buffer BatchProbes { int batch_probes[]; };
uniform int uBatchCount;
shared vec3 partial[64][SH_MAX];
shared vec2 partial_faces[64];  // (hits, back faces)
void main() {
  int probe = uBatchCount > 0 ? batch_probes[gl_WorkGroupID.x] : int(gl_WorkGroupID.x);
  int lane = int(gl_LocalInvocationIndex);
  ivec2 origin = ivec2(probe % uAtlasTiles, probe / uAtlasTiles) * uFaceSize;
  vec3 c[SH_MAX];
  for (int k = 0; k < SH_MAX; ++k) c[k] = vec3(0.0);
  vec2 faces = vec2(0.0);
  int per_face = uFaceSize * uFaceSize;
  for (int t = lane; t < 6 * per_face; t += 64) {
    int face = t / per_face;
    ivec2 ij = ivec2((t % per_face) % uFaceSize, (t % per_face) / uFaceSize);
    ivec3 atlas = ivec3(origin + ij, face);
    if (texelFetch(uProbeDistance, atlas, 0).r > 0.0) {
      faces += vec2(1.0, texelFetch(uProbeNormal, atlas, 0).w > 0.5 ? 1.0 : 0.0);
    }
    vec3 l = imageLoad(uRadiance, atlas).rgb * TexelSolidAngle(ij, uFaceSize);
    float y[SH_MAX];
    ShBasis(TexelDirection(face, ij, uFaceSize), y);
    for (int k = 0; k < uCoefficients; ++k) c[k] += l * y[k];
  }
  for (int k = 0; k < SH_MAX; ++k) partial[lane][k] = c[k];
  partial_faces[lane] = faces;
  barrier();
  for (int stride = 32; stride > 0; stride >>= 1) {
    if (lane < stride) {
      for (int k = 0; k < SH_MAX; ++k) partial[lane][k] += partial[lane + stride][k];
      partial_faces[lane] += partial_faces[lane + stride];
    }
    barrier();
  }
  if (lane == 0) {
    for (int k = 0; k < SH_MAX; ++k) {
      vec3 v = k < uCoefficients ? FiniteOrZero(partial[0][k]) : vec3(0.0);
      coefficients[k * uProbeCount + probe] = vec4(v, 0.0);
    }
    vec2 f = partial_faces[0];
    probe_valid[probe] = f.y > 0.5 * f.x ? 0.0 : 1.0;
  }
}
