#version 450 core
#ifdef GS_LAYER_FROM_VERTEX
#extension GL_ARB_shader_viewport_layer_array : require
#endif
// Distance cubes (render/shadow_maps, avg's VPL cubes). Drawn from a draw
// list (scene/gpu/draw_list.h, GS_DRAW_LIST) whose records' tags are faces
// (DrawTags::kEachBit): each instance projects the draw onto its one face.
// With GS_LAYER_FROM_VERTEX (ARB_shader_viewport_layer_array) this shader
// writes the layer and there is no geometry shader; else
// shadow_cube.geom.glsl emits each triangle into its face. Without
// GS_DRAW_LIST (item by item, uModel) the geometry shader draws every
// triangle into all six faces.
#include "common/scene_vertex.glsl"
#if defined(GS_DRAW_LIST) && defined(GS_LAYER_FROM_VERTEX)
uniform mat4 uFaceViewProj[6];
uniform int uCube;  // cube index in the array
out vec3 gWorld;
void main() {
  const int face = DrawTag();
  const vec4 world = WorldPosition();
  gWorld = world.xyz;
  gl_Position = uFaceViewProj[face] * world;
  gl_Layer = uCube * 6 + face;
}
#else
flat out int vFaces;  // bit f: draw into face f
void main() {
  gl_Position = WorldPosition();
#ifdef GS_DRAW_LIST
  vFaces = 1 << DrawTag();
#else
  vFaces = 0x3f;
#endif
}
#endif
