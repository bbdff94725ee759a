#version 450 core
// The direct light's exitant radiance per directional bin at every glossy
// leaf (antiradiance's glossy local pass, solvers/antiradiance/
// glossy_transfer.h): DirectReflected toward each bin's main direction with
// the leaf's BRDF, its roughness raised to what the bins resolve (as the
// transfer matrix), so the direct highlight lands in the bins as the
// indirect one does. One invocation per (glossy leaf, bin).
#include "antiradiance/bindings.glsl"
layout(local_size_x = 64) in;
#include "render/direct_light.glsl"
#include "antiradiance/glossy.glsl"
struct GlossyElement {
  vec4 position;       // xyz centre
  vec4 normal;         // xyz unit normal, w roughness (raised to the bins')
  vec4 base_metallic;  // rgb base colour, a metallic
  vec4 specular;       // rgb dielectric F0, a dielectric F90 (the material's, issue 29)
};
layout(std430, binding = AR_BINDING_GLOSSY_ELEMENTS) readonly buffer GlossyElements { GlossyElement glossy_elements[]; };
layout(std430, binding = AR_BINDING_GLOSSY_DIRECT) writeonly buffer GlossyDirect { vec4 glossy_direct[]; };
uniform int uCount;
void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= uCount * uBins) return;
  GlossyElement e = glossy_elements[id / uBins];
  vec3 v = bin_direction[id % uBins].xyz;
  vec3 l = vec3(0.0);
  if (dot(e.normal.xyz, v) > 0.0) {
    SurfaceBrdf b = SurfaceBrdf(e.base_metallic.rgb, e.base_metallic.a, e.normal.w, e.specular);
    l = FiniteOrZero(DirectReflected(e.position.xyz, e.normal.xyz, v, b));
  }
  glossy_direct[id] = vec4(l, 0.0);
}
