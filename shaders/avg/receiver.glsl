// `avg`: the receiver's BRDF as its illuminate and filter passes see it
// (common/brdf.glsl, the G-buffer's metallic and roughness).
//
// Both split targets hold irradiance-like values, so the filter averages
// like with like: E itself for Lambertian receivers (the filter applies
// albedo / pi after filtering, as before glossy materials), and for glossy
// ones the reflected radiance demodulated by the BRDF's directional albedo,
// pi L / a(v) (BrdfUniformAlbedo), which is exactly E when the light
// arrives from all directions alike; the filter multiplies a(v) / pi back.
#include "common/brdf.glsl"
layout(binding = 10) uniform sampler2D uGAlbedo;    // a: metallic
layout(binding = 11) uniform sampler2D uGEmission;  // a: roughness
uniform vec3 uCameraPos;

SurfaceBrdf ReceiverBrdf(ivec2 px) {
  vec4 albedo = texelFetch(uGAlbedo, px, 0);
  return SurfaceBrdf(albedo.rgb, albedo.a, texelFetch(uGEmission, px, 0).a);
}

// Unit direction from p (normal n, facing the viewer) to the eye.
vec3 ReceiverView(vec3 p, vec3 n) { return SafeNormalize(uCameraPos - p, n); }

// a(v): base colour for Lambertian receivers; kept above 1e-4 so that
// demodulating and remodulating is exact (a black metal seen head-on
// reflects almost nothing: a(v) = B of the table ~ 0).
vec3 ReceiverAlbedo(SurfaceBrdf b, vec3 n, vec3 v) {
  if (BrdfLambertian(b)) return b.base_color;
  return max(BrdfUniformAlbedo(b, n, v), vec3(1e-4));
}
