// Real spherical harmonics, bands l <= 2 (Nijasure et al. 2005, Eq. 7), the
// probes' cube-map face table and texel solid angles (Eq. 2). Twin of
// server/solvers/sh_probes/spherical_harmonics.cpp.
#include "common/math.glsl"

const int SH_MAX = 9;

void ShBasis(vec3 d, out float y[SH_MAX]) {
  y[0] = 0.282094791773878;
  y[1] = 0.488602511902920 * d.y;
  y[2] = 0.488602511902920 * d.z;
  y[3] = 0.488602511902920 * d.x;
  y[4] = 1.092548430592079 * d.x * d.y;
  y[5] = 1.092548430592079 * d.y * d.z;
  y[6] = 0.315391565252520 * (3.0 * d.z * d.z - 1.0);
  y[7] = 1.092548430592079 * d.x * d.z;
  y[8] = 0.546274215296040 * (d.x * d.x - d.y * d.y);
}

// Eq. 4 with Eq. 6: clamped-cosine convolution factor of coefficient k.
float LambertFactor(int k) { return k == 0 ? PI : (k < 4 ? 2.0 * PI / 3.0 : 0.25 * PI); }

const vec3 FACE_FORWARD[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0),
                                     vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1));
const vec3 FACE_UP[6] = vec3[6](vec3(0, 1, 0), vec3(0, 1, 0), vec3(0, 0, -1),
                                vec3(0, 0, 1), vec3(0, 1, 0), vec3(0, 1, 0));

vec3 FaceRight(int f) { return cross(FACE_FORWARD[f], FACE_UP[f]); }

// Direction through the centre of texel `ij` of a `size` face.
// The direction through point xy of a face (texel units: texel ij spans
// [ij, ij + 1]).
vec3 FaceDirection(int face, vec2 xy, int size) {
  vec2 uv = 2.0 * xy / float(size) - 1.0;
  return normalize(FACE_FORWARD[face] + uv.x * FaceRight(face) + uv.y * FACE_UP[face]);
}

vec3 TexelDirection(int face, ivec2 ij, int size) { return FaceDirection(face, vec2(ij) + 0.5, size); }

float AreaElement(float x, float y) { return atan(x * y, sqrt(x * x + y * y + 1.0)); }

// Exact solid angle of a texel: the A(omega) of Eq. 2.
float TexelSolidAngle(ivec2 ij, int size) {
  vec2 a = 2.0 * vec2(ij) / float(size) - 1.0;
  vec2 b = 2.0 * vec2(ij + 1) / float(size) - 1.0;
  return AreaElement(a.x, a.y) - AreaElement(a.x, b.y) - AreaElement(b.x, a.y) +
         AreaElement(b.x, b.y);
}

// The face and texel a direction falls in.
void DirectionToTexel(vec3 d, int size, out int face, out ivec2 ij) {
  vec3 a = abs(d);
  if (a.x >= a.y && a.x >= a.z) face = d.x >= 0.0 ? 0 : 1;
  else if (a.y >= a.z) face = d.y >= 0.0 ? 2 : 3;
  else face = d.z >= 0.0 ? 4 : 5;
  float w = max(dot(d, FACE_FORWARD[face]), 1e-30);
  vec2 uv = vec2(dot(d, FaceRight(face)), dot(d, FACE_UP[face])) / w;
  ij = clamp(ivec2(floor((uv * 0.5 + 0.5) * float(size))), ivec2(0), ivec2(size - 1));
}
