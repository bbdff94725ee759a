#version 450 core
// The G-buffer's vertices, from a draw list (GS_DRAW_LIST, render/view_passes.cpp).
#include "common/scene_vertex.glsl"
uniform mat4 uViewProj;
out vec3 vWorld;
out vec3 vNormal;
out vec2 vUv;
flat out int vMaterial;
void main() {
  vec4 world = WorldPosition();
  vWorld = world.xyz;
  vNormal = WorldNormal();
  vUv = aUv;
  vMaterial = DrawMaterial();
  gl_Position = uViewProj * world;
}
