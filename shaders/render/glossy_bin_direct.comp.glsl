#version 450 core
// The direct light's exitant radiance per directional bin at glossy
// elements (render/glossy_bin_direct.h): DirectReflected toward each bin's
// main direction with the element's BRDF, its roughness raised to what the
// bins resolve by the caller, so a direct highlight lands in the bins as
// the indirect one does. uBinOmega > 0 widens the lobe by the bin's solid
// angle (BinBrdf; a lobe about as wide as a bin, point-sampled at the
// centres, put 0.84-1.15x of its light into the room as the bins' count
// varied); 0 takes the BRDF at the centre. One invocation per (element,
// bin); the elements are glossy (a Lambertian one would ignore v). antiradiance's
// glossy leaves (Dachsbacher et al. 2007, Section 3.1's local pass with a
// general BRDF) and
// implicit_visibility's glossy elements (Dong et al. 2007, Section 4.3:
// outgoing radiance stored per direction) use it.
#include "bindings.glsl"
#include "common/brdf.glsl"
layout(local_size_x = 64) in;
uniform float uBinOmega;  // sr: the solid angle a bin stands for (0: its centre alone)
// The BRDF toward a bin, widened to the bin's solid angle as
// BrdfEvalSource widens it to an area sample's (alpha^2 + omega / (2 pi),
// D stays normalized): the bin holds its lobe's mean over its directions,
// not the value at its centre. DirectReflected applies it to each light
// (DIRECT_VIEW_BRDF).
vec3 BinBrdf(SurfaceBrdf b, vec3 n, vec3 v, vec3 l) {
  if (!(uBinOmega > 0.0) || BrdfLambertian(b)) return BrdfEval(b, n, v, l);
  float alpha = BrdfAlpha(b);
  SurfaceBrdf w = b;
  w.roughness = sqrt(sqrt(min(alpha * alpha + uBinOmega * (0.5 * INV_PI), 1.0)));
  return BrdfEval(w, n, v, l);
}
#define DIRECT_VIEW_BRDF BinBrdf
#include "render/direct_light.glsl"
struct GlossyBinElement {
  vec4 position;       // xyz centre
  vec4 normal;         // xyz unit normal, w roughness (raised to the bins')
  vec4 base_metallic;  // rgb base colour, a metallic
  vec4 specular;       // rgb dielectric F0, a dielectric F90 (the material's)
};
layout(std430, binding = GS_BINDING_GLOSSY_BIN_ELEMENTS) readonly buffer Elements { GlossyBinElement elements[]; };
layout(std430, binding = GS_BINDING_GLOSSY_BIN_DIRECTIONS) readonly buffer BinDirections { vec4 bin_direction[]; };
layout(std430, binding = GS_BINDING_GLOSSY_BIN_RADIANCE) writeonly buffer Radiance { vec4 radiance[]; };
uniform int uCount;
uniform int uBins;
void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= uCount * uBins) return;
  GlossyBinElement e = elements[id / uBins];
  vec3 v = bin_direction[id % uBins].xyz;
  SurfaceBrdf b = SurfaceBrdf(e.base_metallic.rgb, e.base_metallic.a, e.normal.w, e.specular);
  vec3 l = FiniteOrZero(DirectReflected(e.position.xyz, e.normal.xyz, v, b));
  radiance[id] = vec4(l, 0.0);
}
