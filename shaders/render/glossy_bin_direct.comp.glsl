#version 450 core
// The direct light's exitant radiance per directional bin at glossy
// elements (render/glossy_bin_direct.h): DirectReflected toward each bin's
// main direction with the element's BRDF, its roughness raised to what the
// bins resolve by the caller, so a direct highlight lands in the bins as
// the indirect one does. uSubSamples 7 averages the bin's centre and six
// directions at uSubRadius around it (a lobe about as wide as a bin
// point-sampled at the centres put 0.94-1.06 of its light into the room
// as the bins' count varied; averaged, the bin holds its mean radiance);
// 1 takes the centre alone. One invocation per (element, bin); directions
// below the element's horizon add zero. antiradiance's glossy leaves (Dachsbacher et
// al. 2007, Section 3.1's local pass with a general BRDF) and
// implicit_visibility's glossy elements (Dong et al. 2007, Section 4.3:
// outgoing radiance stored per direction) use it.
#include "bindings.glsl"
layout(local_size_x = 64) in;
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
uniform int uSubSamples;  // 1 or 7
uniform float uSubRadius;  // radians: half the bin's radius
void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= uCount * uBins) return;
  GlossyBinElement e = elements[id / uBins];
  vec3 centre = bin_direction[id % uBins].xyz;
  vec3 du = normalize(cross(abs(centre.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0), centre));
  vec3 dv = cross(centre, du);
  SurfaceBrdf b = SurfaceBrdf(e.base_metallic.rgb, e.base_metallic.a, e.normal.w, e.specular);
  vec3 l = vec3(0.0);
  for (int q = 0; q < uSubSamples; ++q) {
    float phi = 2.0 * PI * float(q) / float(max(1, uSubSamples - 1));
    vec3 v = q == 0 ? centre : normalize(centre + uSubRadius * (cos(phi) * du + sin(phi) * dv));
    if (dot(e.normal.xyz, v) > 0.0)
      l += FiniteOrZero(DirectReflected(e.position.xyz, e.normal.xyz, v, b));
  }
  radiance[id] = vec4(l / float(uSubSamples), 0.0);
}
