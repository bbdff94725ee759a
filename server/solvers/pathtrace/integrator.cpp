#include "solvers/pathtrace/integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scene/texture_lookup.h"
#include "util/constants.h"

namespace gistream::pathtrace {

using namespace shading;  // the shared BRDF and sampling (solvers/shading/)
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

}  // namespace

Integrator::Surface Integrator::Shade(const Hit& hit, const glm::vec3& dir) const {
  const Triangle& t = bvh_.triangles()[hit.triangle];
  const float w = 1.0f - hit.u - hit.v;
  Surface s;
  s.position = t.p0 + hit.u * t.e1 + hit.v * t.e2;
  glm::vec3 n = w * t.n0 + hit.u * t.n1 + hit.v * t.n2;
  const float len = glm::length(n);
  n = len > 0.0f ? n / len : t.normal;
  const bool front = glm::dot(t.normal, dir) < 0.0f;
  s.geometric = front ? t.normal : -t.normal;
  s.normal = glm::dot(n, s.geometric) < 0.0f ? -n : n;
  s.wo = -dir;
  Basis(s.normal, s.tangent, s.bitangent);
  const Material* m = t.material >= 0 ? &state_.materials()[size_t(t.material)] : nullptr;
  glm::vec3 albedo = m ? glm::vec3(m->base_color_factor) : glm::vec3(1.0f);
  const glm::vec2 uv = w * t.uv0 + hit.u * t.uv1 + hit.v * t.uv2;
  if (m && m->base_color_texture >= 0) {
    albedo *= SampleImage(state_.scene().images[size_t(m->base_color_texture)],
                          m->base_color_uv.Apply(uv), m->base_color_sampler);
  }
  s.brdf.base_color = glm::clamp(albedo, 0.0f, 1.0f);
  if (m) {
    s.brdf.metallic = m->metallic_factor;
    s.brdf.roughness = m->roughness_factor;
    s.brdf.specular_f0 = m->specular_f0;
    s.brdf.specular_f90 = m->specular_f90;
    if (m->metallic_roughness_texture >= 0) {
      // glTF 2.0 3.9.2: B metallic, G roughness, linear.
      const glm::vec3 mr =
          SampleImage(state_.scene().images[size_t(m->metallic_roughness_texture)],
                      m->metallic_roughness_uv.Apply(uv), m->metallic_roughness_sampler);
      s.brdf.metallic = std::clamp(s.brdf.metallic * mr.b, 0.0f, 1.0f);
      s.brdf.roughness = std::clamp(s.brdf.roughness * mr.g, 0.0f, 1.0f);
    }
  }
  // Emitters emit on the side their authored normals face, and from both
  // faces when the material is doubleSided (glTF 2.0 3.9.2: the back face is
  // a surface with the flipped normal).
  s.emission = (m && (front || t.double_sided) && t.emitter >= 0) ? Emission(t, hit.u, hit.v)
                                                                  : glm::vec3(0.0f);
  return s;
}

glm::vec3 Integrator::Surface::ToLocal(const glm::vec3& w) const {
  return glm::vec3(glm::dot(w, tangent), glm::dot(w, bitangent), glm::dot(w, normal));
}

glm::vec3 Integrator::Surface::FCos(const glm::vec3& wi) const {
  const float cos_i = glm::dot(normal, wi);
  if (brdf.Lambertian()) return brdf.base_color / kPi * cos_i;
  return Eval(brdf, ToLocal(wo), ToLocal(wi)) * cos_i;
}

float Integrator::Surface::Pdf(const glm::vec3& wi) const {
  if (brdf.Lambertian()) return glm::dot(normal, wi) / kPi;
  return shading::Pdf(brdf, ToLocal(wo), ToLocal(wi));
}

glm::vec3 Integrator::Emission(const Triangle& t, float u, float v) const {
  const Material& m = state_.materials()[size_t(t.material)];
  glm::vec3 e = m.emission();
  if (m.emissive_texture >= 0) {
    const glm::vec2 uv = (1.0f - u - v) * t.uv0 + u * t.uv1 + v * t.uv2;
    e *= SampleImage(state_.scene().images[size_t(m.emissive_texture)], m.emissive_uv.Apply(uv),
                     m.emissive_sampler);
  }
  return e;
}

glm::vec3 Integrator::Environment(const glm::vec3& dir) const {
  if (!env_) return glm::vec3(0.0f);
  return env_->Radiance(dir, state_.environment_rotation()) * state_.environment_intensity();
}

glm::vec3 Integrator::Offset(const Surface& s, const glm::vec3& towards) const {
  // Relative epsilon: scale-invariant from millimetres to kilometres.
  const float eps = 1e-5f * bvh_.scene_scale() + 1e-6f * glm::length(s.position);
  return s.position + (glm::dot(towards, s.geometric) >= 0.0f ? eps : -eps) * s.geometric;
}

float Integrator::AreaLightPdf(const Triangle& t, float distance, float cos_y) const {
  if (t.double_sided) cos_y = std::abs(cos_y);  // either face emits
  if (cos_y <= 0.0f || bvh_.emitter_total() <= 0.0) return 0.0f;
  const Material& m = state_.materials()[size_t(t.material)];
  // pdf per area = lum(L_e) faces / sum(lum(L_e) A faces) (faces = 2 for a
  // double-sided emitter, as it is chosen by power); to solid angle:
  // * d^2 / cos.
  const double faces = t.double_sided ? 2.0 : 1.0;
  const float pdf_area = float(double(Luminance(m.emission())) * faces / bvh_.emitter_total());
  return pdf_area * distance * distance / cos_y;
}

glm::vec3 Integrator::SampleAreaLights(const Surface& s, Rng& rng, PathStats& stats) const {
  const auto& cdf = bvh_.emitter_cdf();
  if (bvh_.emitters().empty()) return glm::vec3(0.0f);
  const double u = double(rng.Uniform()) * bvh_.emitter_total();
  const size_t k = std::min(size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()) - 1,
                            bvh_.emitters().size() - 1);
  const Triangle& t = bvh_.triangles()[bvh_.emitters()[k]];
  float a = rng.Uniform(), b = rng.Uniform();
  if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
  const glm::vec3 y = t.p0 + a * t.e1 + b * t.e2;
  glm::vec3 d = y - s.position;
  const float dist = glm::length(d);
  if (!(dist > 0.0f)) return glm::vec3(0.0f);
  d /= dist;
  const float cos_x = glm::dot(s.normal, d);
  const float cos_y = t.double_sided ? std::abs(glm::dot(t.normal, d)) : -glm::dot(t.normal, d);
  // Below the geometric surface the BSDF sampler cannot go either.
  if (cos_x <= 0.0f || cos_y <= 0.0f || glm::dot(s.geometric, d) <= 0.0f) return glm::vec3(0.0f);
  const float pdf_light = AreaLightPdf(t, dist, cos_y);
  if (!(pdf_light > 0.0f) || !std::isfinite(pdf_light)) return glm::vec3(0.0f);
  // The shadow ray runs between the two surfaces' offset points. The
  // light's end is lifted off the emitter towards the shading point too:
  // ending short of the emitter by a fraction of the distance left the ray
  // within float error of the emitter's plane at grazing angles, and the
  // emitter occluded itself (a ceiling 1 cm above a lamp got 1-40 % of its
  // light, tests/gl/near_field_emitter_test.cpp).
  const glm::vec3 origin = Offset(s, d);
  const float eps = 1e-5f * bvh_.scene_scale() + 1e-6f * glm::length(y);
  const glm::vec3 target = y + (glm::dot(t.normal, origin - y) >= 0.0f ? eps : -eps) * t.normal;
  const glm::vec3 to_target = target - origin;
  const float shadow_length = glm::length(to_target);
  ++stats.rays;
  if (shadow_length > 0.0f &&
      bvh_.Occluded(origin, to_target / shadow_length, shadow_length * (1.0f - 1e-6f))) {
    return glm::vec3(0.0f);
  }
  const float pdf_bsdf = s.Pdf(d);
  const glm::vec3 le = Emission(t, a, b);
  // f L cos / p, weighted by the power heuristic.
  return s.FCos(d) * le * (PowerHeuristic(pdf_light, pdf_bsdf) / pdf_light);
}

glm::vec3 Integrator::SamplePunctualLights(const Surface& s, PathStats& stats) const {
  glm::vec3 sum(0.0f);
  for (const LightInstance& l : state_.lights()) {
    const glm::vec3 intensity = l.light.color * l.light.intensity;
    if (l.light.type == LightType::kDirectional) {
      const glm::vec3 wi = -l.direction;
      const float c = glm::dot(s.normal, wi);
      if (c <= 0.0f || glm::dot(s.geometric, wi) <= 0.0f) continue;
      ++stats.rays;
      if (bvh_.Occluded(Offset(s, wi), wi, kInfinity)) continue;
      sum += intensity * s.FCos(wi);  // f x illuminance (lux) x cos
      continue;
    }
    glm::vec3 d = l.position - s.position;
    const float r2 = glm::dot(d, d);
    if (!(r2 > 0.0f)) continue;
    const float r = std::sqrt(r2);
    d /= r;
    const float c = glm::dot(s.normal, d);
    if (c <= 0.0f || glm::dot(s.geometric, d) <= 0.0f) continue;
    float cone = 1.0f;
    if (l.light.type == LightType::kSpot) {
      const float cos_outer = std::cos(l.light.outer_cone_angle);
      const float scale = 1.0f / std::max(0.001f, std::cos(l.light.inner_cone_angle) - cos_outer);
      cone = std::clamp(glm::dot(l.direction, -d) * scale - cos_outer * scale, 0.0f, 1.0f);
      cone *= cone;
      if (cone <= 0.0f) continue;
    }
    const glm::vec3 origin = Offset(s, d);
    ++stats.rays;
    if (bvh_.Occluded(origin, d, glm::length(l.position - origin))) continue;
    sum += intensity * s.FCos(d) * (cone / r2);  // f I cos / r^2
  }
  return sum;
}

glm::vec3 Integrator::SampleEnvironment(const Surface& s, Rng& rng, PathStats& stats) const {
  if (!env_ || env_->empty() || !(state_.environment_intensity() > 0.0f)) return glm::vec3(0.0f);
  const float rotation = state_.environment_rotation();
  float pdf_sampled = 0.0f;
  const float u1 = rng.Uniform(), u2 = rng.Uniform();
  const glm::vec3 d = env_->Sample(u1, u2, rotation, pdf_sampled);
  if (!(pdf_sampled > 0.0f)) return glm::vec3(0.0f);
  // The pdf of the texel the direction lands in (the one Radiance reads):
  // the same function weighs escaping BSDF paths below.
  const float pdf_env = env_->Pdf(d, rotation);
  const float cos_x = glm::dot(s.normal, d);
  if (!(pdf_env > 0.0f) || cos_x <= 0.0f || glm::dot(s.geometric, d) <= 0.0f) {
    return glm::vec3(0.0f);
  }
  ++stats.rays;
  if (bvh_.Occluded(Offset(s, d), d, kInfinity)) return glm::vec3(0.0f);
  const float pdf_bsdf = s.Pdf(d);
  return s.FCos(d) * Environment(d) * (PowerHeuristic(pdf_env, pdf_bsdf) / pdf_env);
}

glm::vec3 Integrator::Li(glm::vec3 origin, glm::vec3 dir, Rng& rng, PathStats& stats) const {
  glm::vec3 radiance(0.0f), beta(1.0f);
  float pdf_bsdf = 0.0f;  // solid-angle pdf of the direction that led here; 0: camera ray
  for (int depth = 0;; ++depth) {
    ++stats.rays;
    const Hit hit = bvh_.Intersect(origin, dir, kInfinity);
    if (!hit.hit) {
      if (pdf_bsdf == 0.0f || !env_) {
        radiance += beta * Environment(dir);
      } else {
        // Reached by BSDF sampling: weigh against environment sampling.
        const float pdf_env = env_->empty() ? 0.0f : env_->Pdf(dir, state_.environment_rotation());
        radiance += beta * Environment(dir) * PowerHeuristic(pdf_bsdf, pdf_env);
      }
      break;
    }
    const Surface s = Shade(hit, dir);
    if (s.emission != glm::vec3(0.0f)) {
      if (pdf_bsdf == 0.0f) {
        radiance += beta * s.emission;
      } else {
        // Reached by BSDF sampling: weigh against area-light sampling.
        const Triangle& t = bvh_.triangles()[hit.triangle];
        const float pdf_light = AreaLightPdf(t, hit.t, -glm::dot(t.normal, dir));
        radiance += beta * s.emission * PowerHeuristic(pdf_bsdf, pdf_light);
      }
    }
    if ((settings_.max_depth > 0 && depth >= settings_.max_depth) ||
        depth >= IntegratorSettings::kSafetyDepth) {
      break;
    }
    radiance += beta * (SampleAreaLights(s, rng, stats) + SamplePunctualLights(s, stats) +
                        SampleEnvironment(s, rng, stats));

    glm::vec3 next;
    if (s.brdf.Lambertian()) {
      // Cosine sampling of the Lambertian BSDF: f cos / p = albedo.
      next = SampleCosine(s.normal, rng.Uniform(), rng.Uniform());
      const float cos_next = glm::dot(next, s.normal);
      if (cos_next <= 0.0f || glm::dot(next, s.geometric) <= 0.0f) break;
      beta *= s.brdf.base_color;
      pdf_bsdf = cos_next / kPi;
    } else {
      // Visible-normal or cosine sampling of the glossy BRDF (ggx.h).
      const float u1 = rng.Uniform(), u2 = rng.Uniform(), u3 = rng.Uniform();
      const BrdfSample b = Sample(s.brdf, s.ToLocal(s.wo), glm::vec3(u1, u2, u3));
      if (!(b.pdf > 0.0f)) break;
      next = glm::normalize(b.wi.x * s.tangent + b.wi.y * s.bitangent + b.wi.z * s.normal);
      if (glm::dot(next, s.geometric) <= 0.0f) break;
      beta *= b.weight;
      pdf_bsdf = b.pdf;
    }
    if (depth >= 3) {
      // Russian roulette, survival q = max(beta) (at most 1; after the
      // division beta's largest component is 1, so from then on q is the
      // surface's albedo). Unbiased: E[beta / q * [survive]] = beta. A
      // survival cap below 1 (the former 0.95) made the variance infinite
      // for rho^2 / 0.95 >= 1, i.e. rho >= 0.975: E[X^2] ~ sum (rho^2/q)^k.
      // With q = rho it is sum rho^k, finite for every rho < 1.
      const float q = std::min(std::max({beta.r, beta.g, beta.b}), 1.0f);
      if (!(q > 0.0f)) break;
      if (q < 1.0f) {
        if (rng.Uniform() >= q) break;
        beta /= q;
      }
    }
    origin = Offset(s, next);
    dir = next;
  }
  return radiance;
}

}  // namespace gistream::pathtrace
