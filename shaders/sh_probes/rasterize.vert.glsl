#version 450 core
// rasterize_cubemaps: one instance per probe, or per listed probe of a
// batch (uBatchCount > 0, sh_probes' progressive update), or probe
// uProbe >= 0 alone (one instance).
#include "common/scene_vertex.glsl"
out vec3 vWorld;
out vec3 vNormal;
out vec2 vUv;
flat out int vProbe;
layout(std430, binding = 10) readonly buffer BatchProbes { int batch_probes[]; };
uniform int uBatchCount;
uniform int uProbe;
void main() {
  vWorld = WorldPosition().xyz;
  vNormal = WorldNormal();
  vUv = aUv;
  int slot = gl_InstanceID;
  vProbe = uProbe >= 0 ? uProbe : (uBatchCount > 0 ? batch_probes[slot] : slot);
  gl_Position = vec4(vWorld, 1.0);
}
