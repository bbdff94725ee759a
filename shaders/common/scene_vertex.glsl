// The scene's vertex attributes (GpuScene's interleaved layout) and their
// world-space transform: every pass that rasterises the scene reads its
// vertices through these, so the layout lives in one place.
#include "common/scene.glsl"
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;

vec4 WorldPosition() { return uModel * vec4(aPosition, 1.0); }
vec3 WorldNormal() { return uNormalMatrix * aNormal; }
