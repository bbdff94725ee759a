// The scene's vertex attributes (GpuScene's interleaved layout) and their
// world-space transform: every pass that rasterises the scene reads its
// vertices through these, so the layout lives in one place.
//
// With GS_DRAW_LIST defined (a program drawn from a scene/draw_list.h
// list), the transform and a pass-defined tag come from the draw's record,
// read as instanced attributes (a command's base instance plus the
// instance picks it), instead of the uModel uniform.
#include "common/scene.glsl"
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;

#ifdef GS_DRAW_LIST
layout(location = 3) in mat4 aDrawModel;  // locations 3-6
layout(location = 7) in int aDrawTag;

vec4 WorldPosition() { return aDrawModel * vec4(aPosition, 1.0); }
int DrawTag() { return aDrawTag; }
#else
vec4 WorldPosition() { return uModel * vec4(aPosition, 1.0); }
vec3 WorldNormal() { return uNormalMatrix * aNormal; }
#endif
