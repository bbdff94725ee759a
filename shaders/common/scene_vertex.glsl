// The scene's vertex attributes (GpuScene's interleaved layout) and their
// world-space transform: every pass that rasterises the scene reads its
// vertices through these, so the layout lives in one place.
//
// With GS_DRAW_LIST defined (a program drawn from a scene/gpu/draw_list.h
// list), the transform, a pass-defined tag and the material index come
// from the draw's record, read as instanced attributes (a command's base
// instance plus the instance picks it), instead of the uModel, uNormalMatrix
// and uMaterial uniforms.
#include "common/scene.glsl"
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;

#ifdef GS_DRAW_LIST
layout(location = 3) in mat4 aDrawModel;  // locations 3-6
layout(location = 7) in ivec2 aDrawInfo;  // tag, material

vec4 WorldPosition() { return aDrawModel * vec4(aPosition, 1.0); }
int DrawTag() { return aDrawInfo.x; }
int DrawMaterial() { return aDrawInfo.y; }
// The normal through the model's cofactor matrix, det(M) M^-T, signed by
// det(M): the direction of the inverse transpose, with no inverse. Its
// length is not kept (callers normalize); it is scaled so its largest
// component is 1, whatever the node's scale.
vec3 WorldNormal() {
  mat3 m = mat3(aDrawModel);
  mat3 cofactor = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
  vec3 n = cofactor * aNormal;
  float largest = max(max(abs(n.x), abs(n.y)), abs(n.z));
  float sign = dot(m[0], cofactor[0]) < 0.0 ? -1.0 : 1.0;  // det(M)
  return largest > 0.0 ? n * (sign / largest) : n;
}
#else
vec4 WorldPosition() { return uModel * vec4(aPosition, 1.0); }
vec3 WorldNormal() { return uNormalMatrix * aNormal; }
#endif
