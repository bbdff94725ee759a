#version 450 core
// rasterize_cubemaps: one instance per probe, or per listed probe of a
// batch (uBatchCount > 0, sh_probes' progressive update).
#include "common/scene_vertex.glsl"
out vec3 vWorld;
out vec3 vNormal;
out vec2 vUv;
flat out int vProbe;
layout(std430, binding = 10) readonly buffer BatchProbes { int batch_probes[]; };
uniform int uBatchCount;
void main() {
  vWorld = WorldPosition().xyz;
  vNormal = WorldNormal();
  vUv = aUv;
  vProbe = uBatchCount > 0 ? batch_probes[gl_InstanceID] : gl_InstanceID;
  gl_Position = vec4(vWorld, 1.0);
}
