// Scene data shared by every pass: vertex layout and the material table
// (std430 mirror of gistream::GpuMaterial).
#include "bindings.glsl"
struct Material {
  vec4 base_color;  // linear RGBA
  vec4 emission;    // rgb: emitted radiance (nits)
  ivec4 textures;   // x: base colour, y: emissive, w: metallic-roughness texture or -1;
                    // z: 1 when double-sided
  vec4 pbr;         // x: metallic factor, y: roughness factor
  vec4 specular;    // rgb: dielectric F0, a: dielectric F90 (common/brdf.glsl)
  // KHR_texture_transform rows (xyz: uv' = (dot(row0, (uv, 1)), dot(row1,
  // (uv, 1)))): base colour 0-1, emissive 2-3, metallic-roughness 4-5.
  vec4 uv_transform[6];
};

layout(std430, binding = GS_BINDING_MATERIALS) readonly buffer Materials { Material materials[]; };

uniform int uMaterial;
uniform mat4 uModel;
uniform mat3 uNormalMatrix;
