#version 450 core
// G-buffer: world position (w = 1 where geometry), shading normal facing the
// viewer, linear albedo (a: metallic), emitted radiance (a: roughness).
#include "common/material.glsl"
#include "common/math.glsl"
// The eye: an emitter emits on the side its authored normals face, and
// from both faces when doubleSided (render/area_lights.cpp, pathtrace).
uniform vec3 uEye;
in vec3 vWorld;
in vec3 vNormal;
in vec2 vUv;
flat in int vMaterial;
layout(location = 0) out vec4 oPosition;
layout(location = 1) out vec4 oNormal;
layout(location = 2) out vec4 oAlbedo;
layout(location = 3) out vec4 oEmission;
layout(location = 4) out vec4 oSpecular;  // rgb: dielectric F0, a: F90
void main() {
  Material m = materials[vMaterial];
  vec3 n = SafeNormalize(vNormal, vec3(0.0, 1.0, 0.0));
  bool emitting_side = m.textures.z == 1 || dot(n, uEye - vWorld) >= 0.0;
  // Surfaces are lit on the side the viewer sees.
  if (!gl_FrontFacing) n = -n;
  oPosition = vec4(vWorld, 1.0);
  oNormal = vec4(n, 0.0);
  vec2 mr = SurfaceMetallicRoughness(m, vUv);
  oAlbedo = vec4(SurfaceAlbedo(m, vUv), mr.x);
  vec3 emission = SurfaceEmission(m, vUv);
  oEmission = vec4(emitting_side ? emission : vec3(0.0), mr.y);
  oSpecular = m.specular;
}
