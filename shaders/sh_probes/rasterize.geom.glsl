#version 450 core
// rasterize_cubemaps' geometry-shader fallback: each triangle into the
// faces in vFaces of probe uProbe, each projected onto its face and placed
// in the probe's tile of atlas layer f; clip distances keep it inside the
// tile. One invocation per triangle (llvmpipe runs a geometry shader's
// invocations apart).
layout(triangles) in;
layout(triangle_strip, max_vertices = 18) out;
in vec3 vWorld[];
in vec3 vNormal[];
in vec2 vUv[];
flat in int vFaces[];
flat in int vMaterial[];
out vec3 gWorld;
out vec3 gNormal;
out vec2 gUv;
flat out vec3 gProbe;
flat out int gMaterial;
out float gl_ClipDistance[4];
#include "sh_probes/face_projection.glsl"
uniform int uProbe;
void main() {
  vec3 center = ProbeCenter(uProbe);
  for (int face = 0; face < 6; ++face) {
    if ((vFaces[0] & (1 << face)) == 0) continue;
    vec4 clip[3];
    for (int i = 0; i < 3; ++i) clip[i] = FaceClip(vWorld[i], center, face);
    // Skip faces the triangle cannot touch (all vertices outside one plane).
    bool outside = clip[0].w < uNear && clip[1].w < uNear && clip[2].w < uNear;
    for (int k = 0; k < 2; ++k) {
      outside = outside ||
                (clip[0][k] > clip[0].w && clip[1][k] > clip[1].w && clip[2][k] > clip[2].w) ||
                (clip[0][k] < -clip[0].w && clip[1][k] < -clip[1].w && clip[2][k] < -clip[2].w);
    }
    if (outside) continue;
    for (int i = 0; i < 3; ++i) {
      gl_Position = IntoTile(clip[i], uProbe);
      gWorld = vWorld[i];
      gNormal = vNormal[i];
      gUv = vUv[i];
      gProbe = center;
      gMaterial = vMaterial[0];
      gl_Layer = face;
      EmitVertex();
    }
    EndPrimitive();
  }
}
