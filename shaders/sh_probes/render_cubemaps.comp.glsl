#version 450 core
// render_cubemaps: shade every stored probe texel with direct light (the
// same shadow maps as `direct`) plus the current indirect estimate:
// L = albedo / pi * (E_direct + E_indirect) (Section 3, step 2). Emission
// is not stored: the probes carry reflected light only, since emitters
// already light surfaces through the direct term.
// A glossy surface is shaded as the probe sees it, towards the probe (the
// paper renders the scene into the cube maps, so a probe sees what a
// camera at its centre would): the direct light through the BRDF
// (DirectReflected) and the indirect irradiance times the directional
// albedo a(v) / pi. The gold of a metal cube reaches the probes in its
// lobe, not spread out as if it were a gold-coloured Lambertian surface.
// A point light's highlight spans a few texels of a face, so one sample
// per texel aliased (the gold cube's light on glossy_box's walls came out
// 0.79-1.20x of the path tracer's over face sizes 12-32): glossy texels
// whose lobe is narrow for a texel average up to 3 x 3 points of their
// footprint on the surface's plane (GlossySide).
// uDirect keeps the direct light's reflected radiance towards the probe,
// fixed per texel until the probe is re-rasterized (which recomputes it).
#include "sh_probes/bindings.glsl"
#include "render/direct_light.glsl"
#include "sh_probes/texel.glsl"
#include "sh_probes/batch.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = SH_IMAGE_DIRECT, rgba32f) uniform image2DArray uDirect;
layout(binding = SH_IMAGE_INDIRECT, rgba32f) readonly uniform image2DArray uIndirect;
layout(binding = SH_IMAGE_RADIANCE, rgba32f) writeonly uniform image2DArray uRadiance;
uniform int uComputeDirect;  // 1: recompute the direct light (lights or geometry changed)
uniform int uUseIndirect;    // 0 on the first bounce

const float kMinProbeRoughness = 0.2;

// Points per side for a glossy texel: a highlight spans about alpha
// radians seen from the probe (half the view's and the light's spread
// over it), a texel 2 / face size; 1.5 points per lobe width across the
// texel, at most 3. Gold at roughness 0.3 (alpha 0.09) on a 16-texel face
// takes 3; roughness 0.5 and above, the common exporter default, 1.
int GlossySide(SurfaceBrdf b) {
  float texel = 2.0 / float(uFaceSize);
  return clamp(int(ceil(1.5 * texel / BrdfAlpha(b))), 1, 3);
}

// The direct light a glossy texel reflects towards its probe, averaged
// over the texel: each stratum's direction from the probe meets the plane
// of the surface point the texel stored; a point off that plane's
// footprint (the texel's edge on a silhouette or at grazing view) falls
// back to the stored point.
vec3 GlossyDirect(ProbeTexel t, ivec3 atlas, SurfaceBrdf b) {
  ivec2 tile = atlas.xy / uFaceSize;
  vec2 ij = vec2(atlas.xy - tile * uFaceSize);
  float reach = 4.0 * length(t.position - t.probe) / float(uFaceSize);
  int side = GlossySide(b);
  vec3 sum = vec3(0.0);
  for (int k = 0; k < side * side; ++k) {
    vec2 o = (vec2(k % side, k / side) + 0.5) / float(side);
    vec3 d = FaceDirection(atlas.z, ij + o, uFaceSize);
    float dn = dot(d, t.normal);
    float s = dn < 0.0 ? dot(t.position - t.probe, t.normal) / dn : -1.0;
    vec3 p = t.probe + d * s;
    if (!(s > 0.0) || !(length(p - t.position) <= reach)) p = t.position;
    sum += DirectReflected(p, t.normal, SafeNormalize(t.probe - p, t.normal), b);
  }
  return sum / float(side * side);
}
void main() {
  ivec3 atlas;
  if (!BatchTexel(uFaceSize, uAtlasTiles, atlas)) return;
  if (any(greaterThanEqual(atlas.xy, imageSize(uRadiance).xy))) return;
  ProbeTexel t;
  if (!LoadProbeTexel(atlas, t)) return;
  vec3 l = vec3(0.0);
  if (t.hit) {
    SurfaceBrdf b = ProbeTexelBrdf(t);
    // Near-mirror lobes (roughness under kMinProbeRoughness) stay diffuse
    // of their base colour, as before glossy probes: an area light's
    // samples are points to such a lobe, and one aligned with the mirror
    // direction put a spike of f E into a texel that the probe's SH spread
    // over its whole neighbourhood (a bright square on the assimp corpus's
    // ClearCoatTest.gltf, roughness 0.03, that the path tracer does not show).
    if (b.roughness < kMinProbeRoughness) b = DefaultSpecularBrdf(b.base_color, 0.0, 1.0);
    vec3 v = SafeNormalize(t.probe - t.position, t.normal);
    if (uComputeDirect != 0) {
      l = FiniteOrZero(BrdfLambertian(b) ? DirectReflected(t.position, t.normal, v, b)
                                         : GlossyDirect(t, atlas, b));
      imageStore(uDirect, atlas, vec4(l, 0.0));
    } else {
      l = imageLoad(uDirect, atlas).rgb;
    }
    if (uUseIndirect != 0) {
      l += BrdfUniformAlbedo(b, t.normal, v) * INV_PI * imageLoad(uIndirect, atlas).rgb;
    }
  }
  imageStore(uRadiance, atlas, vec4(l, 0.0));
}
