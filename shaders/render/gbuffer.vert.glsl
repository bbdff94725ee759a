#version 450 core
#include "common/scene_vertex.glsl"
uniform mat4 uViewProj;
out vec3 vWorld;
out vec3 vNormal;
out vec2 vUv;
void main() {
  vec4 world = WorldPosition();
  vWorld = world.xyz;
  vNormal = WorldNormal();
  vUv = aUv;
  gl_Position = uViewProj * world;
}
