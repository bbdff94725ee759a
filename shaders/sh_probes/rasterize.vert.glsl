#version 450 core
// rasterize_cubemaps: one instance per probe.
#include "common/scene.glsl"
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
out vec3 vWorld;
out vec3 vNormal;
out vec2 vUv;
flat out int vProbe;
void main() {
  vWorld = (uModel * vec4(aPosition, 1.0)).xyz;
  vNormal = uNormalMatrix * aNormal;
  vUv = aUv;
  vProbe = gl_InstanceID;
  gl_Position = vec4(vWorld, 1.0);
}
