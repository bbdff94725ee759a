#version 450 core
// rasterize_cubemaps with a geometry shader (rasterize.geom.glsl), where
// the GL cannot write the layer from the vertex shader: the world-space
// vertex, and the faces of probe uProbe to draw it into (the draw record's
// one face from a draw list, GS_DRAW_LIST; item by item, uFaceMask).
#include "common/scene_vertex.glsl"
out vec3 vWorld;
out vec3 vNormal;
out vec2 vUv;
flat out int vFaces;  // bit f: draw into face f
flat out int vMaterial;
#ifndef GS_DRAW_LIST
uniform int uFaceMask;  // render/proxy_filters CubeFaceMask; 63: all
#endif
void main() {
  vWorld = WorldPosition().xyz;
  vNormal = WorldNormal();
  vUv = aUv;
#ifdef GS_DRAW_LIST
  vFaces = 1 << DrawTag();
  vMaterial = DrawMaterial();
#else
  vFaces = uFaceMask;
  vMaterial = uMaterial;
#endif
  gl_Position = vec4(vWorld, 1.0);
}
