#version 450 core
#include "common/scene.glsl"
layout(location = 0) in vec3 aPosition;
uniform mat4 uViewProj;
void main() { gl_Position = uViewProj * uModel * vec4(aPosition, 1.0); }
