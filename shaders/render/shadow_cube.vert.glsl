#version 450 core
#include "common/scene_vertex.glsl"
void main() { gl_Position = WorldPosition(); }
