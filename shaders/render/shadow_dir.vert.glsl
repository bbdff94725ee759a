#version 450 core
#include "common/scene_vertex.glsl"
uniform mat4 uViewProj;
void main() { gl_Position = uViewProj * WorldPosition(); }
