#version 450 core
#extension GL_ARB_shader_viewport_layer_array : require
// rasterize_cubemaps without a geometry shader: instance 6 p + f projects
// the scene onto face f of probe p (or of listed probe p of a batch,
// uBatchCount > 0; or of probe uProbe >= 0 alone, instances 0-5) and writes
// gl_Layer itself; clip distances keep each triangle inside the probe's
// tile, and the clipper drops the triangles a face cannot see, and all of
// a face outside uFaceMask. Same output as rasterize.geom.glsl.
#include "common/scene_vertex.glsl"
out vec3 gWorld;
out vec3 gNormal;
out vec2 gUv;
flat out vec3 gProbe;
out float gl_ClipDistance[4];
#include "sh_probes/face_projection.glsl"
layout(std430, binding = 10) readonly buffer BatchProbes { int batch_probes[]; };
uniform int uBatchCount;
uniform int uProbe;
void main() {
  int slot = gl_InstanceID / 6, face = gl_InstanceID % 6;
  int probe = uProbe >= 0 ? uProbe : (uBatchCount > 0 ? batch_probes[slot] : slot);
  vec3 center = ProbeCenter(probe);
  vec3 world = WorldPosition().xyz;
  gl_Position = IntoTile(FaceClip(world, center, face), probe);
  if (!FaceDrawn(face)) gl_ClipDistance[0] = -1.0;
  gWorld = world;
  gNormal = WorldNormal();
  gUv = aUv;
  gProbe = center;
  gl_Layer = face;
}
