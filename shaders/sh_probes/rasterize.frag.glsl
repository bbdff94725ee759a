#version 450 core
// rasterize_cubemaps: the probes' cube-map G-buffer. Distance to the probe
// (also the depth cube of Section 6), normal turned toward the probe with
// w = 1 where the probe sees a back face, albedo and the material's index,
// metallic and roughness (render_cubemaps shades glossy surfaces towards
// the probe).
#include "common/material.glsl"
#include "common/math.glsl"
in vec3 gWorld;
in vec3 gNormal;
in vec2 gUv;
flat in vec3 gProbe;
flat in int gMaterial;
layout(location = 0) out float oDistance;
layout(location = 1) out vec4 oNormal;
layout(location = 2) out vec4 oAlbedo;
layout(location = 3) out vec2 oMaterial;
void main() {
  Material m = materials[gMaterial];
  vec3 n = SafeNormalize(gNormal, vec3(0.0, 1.0, 0.0));
  bool back = dot(n, gProbe - gWorld) < 0.0;
  if (back) n = -n;
  oDistance = max(length(gWorld - gProbe), 1e-30);
  oNormal = vec4(n, back ? 1.0 : 0.0);
  // a: the material, for its dielectric F0 and F90 (texel.glsl; exact as
  // a float below 2^24).
  oAlbedo = vec4(SurfaceAlbedo(m, gUv), float(gMaterial));
  oMaterial = SurfaceMetallicRoughness(m, gUv);
}
