#version 450 core
// The direct light's exitant radiance per directional bin at glossy
// elements (render/glossy_bin_direct.h): DirectReflected toward each bin's
// main direction with the element's BRDF, its roughness raised to what the
// bins resolve by the caller, so a direct highlight lands in the bins as
// the indirect one does. uSubSamples 7 averages the BRDF over the bin
// (BinBrdf; a lobe about as wide as a bin, point-sampled at the centres,
// put 0.94-1.06x of its light into the room as the bins' count varied);
// 1 takes the centre alone. One invocation per (element, bin); the
// elements are glossy (a Lambertian one would ignore v). antiradiance's
// glossy leaves (Dachsbacher et al. 2007, Section 3.1's local pass with a
// general BRDF) and
// implicit_visibility's glossy elements (Dong et al. 2007, Section 4.3:
// outgoing radiance stored per direction) use it.
#include "bindings.glsl"
#include "common/brdf.glsl"
layout(local_size_x = 64) in;
uniform int uSubSamples;  // 1 (the centre) or 7 (over the bin's disc)
uniform float uBinRadius;  // radians: the radius of a disc of the bin's solid angle
// The BRDF averaged over the bin around v (its centre): the centre and six
// directions at 0.756 of the bin's radius (the middle, by area, of the
// ring they stand for: sqrt(4/7)); directions below the horizon add zero.
// DirectReflected applies it to each light (DIRECT_VIEW_BRDF), so the
// lights and shadow maps are looked up once per bin.
vec3 BinBrdf(SurfaceBrdf b, vec3 n, vec3 v, vec3 l) {
  if (uSubSamples <= 1) return BrdfEval(b, n, v, l);
  vec3 du = normalize(cross(abs(v.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0), v));
  vec3 dv = cross(v, du);
  vec3 f = vec3(0.0);
  for (int q = 0; q < uSubSamples; ++q) {
    float phi = 2.0 * PI * float(q - 1) / float(uSubSamples - 1);
    vec3 w = q == 0 ? v : normalize(v + 0.756 * uBinRadius * (cos(phi) * du + sin(phi) * dv));
    if (dot(n, w) > 0.0) f += BrdfEval(b, n, w, l);
  }
  return f / float(uSubSamples);
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
  // A bin centred below the horizon keeps what its directions above it
  // reflect (BinBrdf; with the centre alone, zero).
  SurfaceBrdf b = SurfaceBrdf(e.base_metallic.rgb, e.base_metallic.a, e.normal.w, e.specular);
  vec3 l = FiniteOrZero(DirectReflected(e.position.xyz, e.normal.xyz, v, b));
  radiance[id] = vec4(l, 0.0);
}
