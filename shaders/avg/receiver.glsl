// `avg`: the receiver's BRDF as its illuminate and filter passes see it
// (common/brdf.glsl, the G-buffer's metallic, roughness and specular).
//
// Both split targets hold irradiance-like values, so the filter averages
// like with like: E itself for Lambertian receivers (the filter applies
// albedo / pi after filtering, as before glossy materials), and for glossy
// ones the reflected radiance demodulated by the BRDF's directional albedo,
// pi L / a(v) (BrdfUniformAlbedo), which is exactly E when the light
// arrives from all directions alike; the filter multiplies a(v) / pi back.
#include "bindings.glsl"
#include "common/brdf.glsl"
layout(binding = GS_UNIT_GBUFFER_ALBEDO) uniform sampler2D uGAlbedo;    // a: metallic
layout(binding = GS_UNIT_GBUFFER_EMISSION) uniform sampler2D uGEmission;  // a: roughness
layout(binding = GS_UNIT_GBUFFER_SPECULAR) uniform sampler2D uGSpecular;  // dielectric F0, F90
uniform vec3 uCameraPos;

SurfaceBrdf ReceiverBrdf(ivec2 px) {
  vec4 albedo = texelFetch(uGAlbedo, px, 0);
  return SurfaceBrdf(albedo.rgb, albedo.a, texelFetch(uGEmission, px, 0).a,
                     texelFetch(uGSpecular, px, 0));
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

// pi f(v, l) / a(v) of one VPL for a glossy receiver at distance r (r2 =
// r^2), its lobe widened to what the VPL stands for. The geometry-term bias
// E = Phi / pi cos_v cos_x / (r^2 + d^2) (illuminate.frag.glsl) is, on the
// axis, exactly the irradiance of a Lambertian disk of radius d emitting
// Phi (M d^2 / (r^2 + d^2), M = Phi / (pi d^2)): the cosine terms already
// see each VPL as that disk. The BRDF sees it too: from the receiver the
// disk fills a cone of half-angle theta, tan theta = d / r, whose
// directions tilt the half vector by up to theta / 2; the GGX slope scale
// alpha and the cone's half-vector slopes add in quadrature (widths of
// convolved slope distributions, exact for Gaussian ones):
//   alpha'^2 = alpha^2 + tan^2(theta / 2),  tan(theta / 2) = d / (r + sqrt(r^2 + d^2)),
// in (0, 1]: far VPLs keep their lobe, one at r -> 0 spreads over the
// hemisphere (the roughness regularisation of Kaplanyan & Dachsbacher 2013
// with the cone of Hasan et al.'s virtual spherical lights, 2009). The
// widened lobe is demodulated by its own directional albedo, so under light
// from all directions alike it returns E exactly as the true lobe does: the
// widening moves energy across the receiver, it adds or removes none of
// the uniform-light response. d = 0 (`clamp=0`) leaves the lobe as it is.
vec3 VplGlossyResponse(SurfaceBrdf b, vec3 n, vec3 v, vec3 l, float r2, float d2) {
  float alpha = BrdfAlpha(b);
  float t = d2 > 0.0 ? sqrt(d2) / (sqrt(r2) + sqrt(r2 + d2)) : 0.0;
  SurfaceBrdf wide = b;
  wide.roughness = min(sqrt(sqrt(alpha * alpha + t * t)), 1.0);  // alpha = roughness^2
  return PI * BrdfEval(wide, n, v, l) / ReceiverAlbedo(wide, n, v);
}
