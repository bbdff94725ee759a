#version 450 core
// Morphing and linear blend skinning of one deforming draw's vertices
// (glTF 2.0 3.7.2.2 "Morph Targets", 3.7.3.3 "Joint Hierarchy"): the GPU
// twin of scene/state/deform.cpp's DeformPrimitive, which is the reference
// (tests/gl/gpu_deform_test.cpp holds this pass to it). Reads the rest
// pose at uSrc, writes the posed vertex at uDst of GpuScene's buffer.
#include "bindings.glsl"
layout(local_size_x = 64) in;

// GpuScene's interleaved vertices: position xyz, normal xyz, uv (8 floats).
layout(std430, binding = GS_BINDING_DEFORM_VERTICES) buffer Vertices { float vertex[]; };
struct SkinVertex {
  uvec4 joints;
  vec4 weights;
};
layout(std430, binding = GS_BINDING_DEFORM_SKIN) readonly buffer Skin { SkinVertex skin[]; };
// Per target, per vertex: position delta, normal delta (xyz).
layout(std430, binding = GS_BINDING_DEFORM_MORPH) readonly buffer Morph { vec4 delta[]; };
// Per joint: J_j, then N_j (the inverse transpose of J_j's upper 3x3).
layout(std430, binding = GS_BINDING_DEFORM_JOINTS) readonly buffer Joints { mat4 joint[]; };
layout(std430, binding = GS_BINDING_DEFORM_WEIGHTS) readonly buffer Weights { float weight[]; };

uniform uint uCount;    // vertices
uniform uint uSrc;      // first rest-pose vertex
uniform uint uDst;      // first posed vertex
uniform int uSkin;      // first SkinVertex, -1: not skinned
uniform uint uMorph;    // first delta
uniform uint uTargets;  // morph targets
uniform uint uJoints;   // first joint matrix
uniform uint uWeights;  // first morph weight

// As DeformPrimitive: a cancelled normal keeps the rest-pose one.
vec3 SafeNormalize(vec3 n, vec3 fallback) {
  float len = length(n);
  return len > 1e-20 && !isinf(len) ? n / len : fallback;
}

vec3 Read(uint v, uint offset) {
  uint i = v * 8u + offset;
  return vec3(vertex[i], vertex[i + 1u], vertex[i + 2u]);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uCount) return;
  vec3 rest_normal = Read(uSrc + i, 3u);
  vec3 p = Read(uSrc + i, 0u);
  vec3 n = rest_normal;
  // Morph: p' = p + sum_t w_t dP_t, n' = n + sum_t w_t dN_t.
  for (uint t = 0u; t < uTargets; ++t) {
    float w = weight[uWeights + t];
    if (w == 0.0) continue;
    uint d = uMorph + 2u * (t * uCount + i);
    p += w * delta[d].xyz;
    n += w * delta[d + 1u].xyz;
  }
  if (uSkin < 0) {
    if (uTargets > 0u) n = SafeNormalize(n, rest_normal);
  } else {
    // Skin: p'' = sum_k W_k (J_{j_k} p'), n'' = normalize(sum_k W_k (N_{j_k} n')).
    SkinVertex s = skin[uint(uSkin) + i];
    vec3 ps = vec3(0.0), ns = vec3(0.0);
    for (int k = 0; k < 4; ++k) {
      float w = s.weights[k];
      if (w == 0.0) continue;
      uint j = uJoints + 2u * s.joints[k];
      ps += w * (joint[j] * vec4(p, 1.0)).xyz;
      ns += w * (mat3(joint[j + 1u]) * n);
    }
    p = ps;
    n = SafeNormalize(ns, rest_normal);
  }
  uint o = (uDst + i) * 8u;
  vertex[o] = p.x;
  vertex[o + 1u] = p.y;
  vertex[o + 2u] = p.z;
  vertex[o + 3u] = n.x;
  vertex[o + 4u] = n.y;
  vertex[o + 5u] = n.z;
}
