// VPLs on the GPU (std430 mirror of server/solvers/avg/vpl_shadow_maps.h)
// and their hemispherical (paraboloid) shadow maps, one layer each.
#include "avg/bindings.glsl"
#include "common/brdf.glsl"
#include "common/math.glsl"

struct Vpl {
  vec4 position_far;         // xyz world position, w: shadow far distance
  vec4 normal_layer;         // xyz unit normal (the lit side), w: shadow layer
  vec4 flux;                 // rgb reflected power (W)
  vec4 incident_roughness;   // xyz unit direction its light came from, w: roughness
  vec4 base_color_metallic;  // the voxel's BRDF: rgb base colour, a: metallic
  vec4 specular;             // its dielectric rgb F0, a F90 (the materials' mean)
};

layout(std430, binding = AVG_BINDING_VPLS) readonly buffer Vpls { Vpl vpls[]; };

// Orthonormal basis (t, b, n) around unit n (Duff et al. 2017), identical
// to the CPU's.
void VplBasis(vec3 n, out vec3 t, out vec3 b) {
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float c = n.x * n.y * a;
  t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
  b = vec3(c, s + n.y * n.y * a, -n.y);
}

// World offset `d` from the VPL -> its local frame (z along the normal).
vec3 VplLocal(Vpl v, vec3 d) {
  vec3 t, b;
  VplBasis(v.normal_layer.xyz, t, b);
  return vec3(dot(d, t), dot(d, b), dot(d, v.normal_layer.xyz));
}

// The BRDF it reflects its light through (Lambertian: metallic 0,
// roughness 1), with its voxel's dielectric F0 and F90 (issue 29).
SurfaceBrdf VplBrdf(Vpl v) {
  return SurfaceBrdf(v.base_color_metallic.rgb, v.base_color_metallic.a, v.incident_roughness.w,
                     v.specular);
}

// Paraboloid map of a unit direction in the upper hemisphere to [-1, 1]^2
// (Brabec et al. 2002): uv = d.xy / (1 + d.z).
vec2 ParaboloidUv(vec3 dir) { return dir.xy / max(1.0 + dir.z, 1e-6); }
