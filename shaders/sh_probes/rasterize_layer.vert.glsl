#version 450 core
#extension GL_ARB_shader_viewport_layer_array : require
// rasterize_cubemaps without a geometry shader: projects the scene onto one
// face of probe uProbe, placed in the probe's tile, and writes gl_Layer
// itself; clip distances keep each triangle inside the tile, and the
// clipper drops the triangles the face cannot see. From a draw list
// (GS_DRAW_LIST, what the solver draws) the face is the record's tag (one
// record per face that may see the node: DrawTags::kEachBit) and the
// material the record's; item by item (the reference tests compare with)
// instance f draws face f, and a face outside uFaceMask draws nothing.
// Same output as rasterize.geom.glsl.
#include "common/scene_vertex.glsl"
out vec3 gWorld;
out vec3 gNormal;
out vec2 gUv;
flat out vec3 gProbe;
flat out int gMaterial;
out float gl_ClipDistance[4];
#include "sh_probes/face_projection.glsl"
uniform int uProbe;
#ifndef GS_DRAW_LIST
// Bit f set: face f may see what is drawn (render/proxy_filters
// CubeFaceMask). 63: all.
uniform int uFaceMask;
#endif
void main() {
#ifdef GS_DRAW_LIST
  int face = DrawTag();
  gMaterial = DrawMaterial();
#else
  int face = gl_InstanceID;
  gMaterial = uMaterial;
#endif
  vec3 center = ProbeCenter(uProbe);
  vec3 world = WorldPosition().xyz;
  gl_Position = IntoTile(FaceClip(world, center, face), uProbe);
#ifndef GS_DRAW_LIST
  if (((uFaceMask >> face) & 1) == 0) gl_ClipDistance[0] = -1.0;
#endif
  gWorld = world;
  gNormal = WorldNormal();
  gUv = aUv;
  gProbe = center;
  gl_Layer = face;
}
