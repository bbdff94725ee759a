#version 450 core
// rasterize_cubemaps: every probe's six faces in one pass. Invocation f
// projects the triangle onto face f of probe vProbe and places it in that
// probe's tile of atlas layer f; clip distances keep it inside the tile.
// Faces outside uFaceMask draw nothing.
layout(triangles, invocations = 6) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 vWorld[];
in vec3 vNormal[];
in vec2 vUv[];
flat in int vProbe[];
out vec3 gWorld;
out vec3 gNormal;
out vec2 gUv;
flat out vec3 gProbe;
out float gl_ClipDistance[4];
#include "sh_probes/face_projection.glsl"
void main() {
  int face = gl_InvocationID;
  if (!FaceDrawn(face)) return;
  int probe = vProbe[0];
  vec3 center = ProbeCenter(probe);
  vec4 clip[3];
  for (int i = 0; i < 3; ++i) clip[i] = FaceClip(vWorld[i], center, face);
  // Skip faces the triangle cannot touch (all vertices outside one plane).
  for (int k = 0; k < 2; ++k) {
    if (clip[0][k] > clip[0].w && clip[1][k] > clip[1].w && clip[2][k] > clip[2].w) return;
    if (clip[0][k] < -clip[0].w && clip[1][k] < -clip[1].w && clip[2][k] < -clip[2].w) return;
  }
  if (clip[0].w < uNear && clip[1].w < uNear && clip[2].w < uNear) return;
  for (int i = 0; i < 3; ++i) {
    gl_Position = IntoTile(clip[i], probe);
    gWorld = vWorld[i];
    gNormal = vNormal[i];
    gUv = vUv[i];
    gProbe = center;
    gl_Layer = face;
    EmitVertex();
  }
  EndPrimitive();
}
