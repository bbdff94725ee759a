// Radiance along one camera ray: unidirectional path tracing with
// next-event estimation. Area lights (emissive triangles) are sampled by
// power and combined with BSDF sampling by multiple importance sampling;
// punctual lights are sampled directly (they cannot be hit); the
// environment is importance-sampled by luminance and combined with the
// BSDF-sampled paths that escape, also by MIS. Surfaces reflect with the
// glTF metallic-roughness BRDF (ggx.h; Lambertian at metallic 0 and
// roughness 1, sampled exactly as before it existed), lit on the side the
// ray arrives from. Paths end only by Russian roulette (after
// three bounces, survival = the throughput's largest component, no cap
// below 1), which keeps the estimator unbiased at any albedo < 1; a bounce
// cap is opt-in (`max_depth`), and kSafetyDepth bounds the work of a path
// whose albedo is exactly 1.
#pragma once

#include <glm/glm.hpp>

#include "scene/state/scene_state.h"
#include "solvers/shading/env_light.h"
#include "solvers/shading/ggx.h"
#include "solvers/shading/sampling.h"
#include "solvers/pathtrace/scene_bvh.h"

namespace gistream::pathtrace {

// The shading math the path tracer shares with the GI solvers
// (solvers/shading/): its BRDF, sampling and environment light.
using shading::Brdf;
using shading::EnvironmentLight;
using shading::Rng;

struct IntegratorSettings {
  // Bounces at most; 0 = no cap (Russian roulette alone ends paths). A cap
  // makes the estimate biased low by the light of the longer paths.
  int max_depth = 0;
  // Hard safety cap, also when max_depth = 0. Roulette survives a bounce
  // with probability about the albedo rho, so P(path > kSafetyDepth) ~
  // rho^kSafetyDepth: e^-65 at rho = 0.999 (mean length 1000), e^-6.6 at
  // rho = 0.9999, and it never ends a path at rho = 1, where only this cap
  // bounds the work (the radiance is then unbounded anyway). The bias it
  // leaves is L * rho^kSafetyDepth, below 1e-28 of L at rho <= 0.999.
  static constexpr int kSafetyDepth = 1 << 16;
};

struct PathStats {
  uint64_t rays = 0;
};

class Integrator {
 public:
  // `env` may be null (no environment map).
  Integrator(const SceneState& state, const SceneBvh& bvh, const EnvironmentLight* env,
             const IntegratorSettings& settings)
      : state_(state), bvh_(bvh), env_(env), settings_(settings) {}

  glm::vec3 Li(glm::vec3 origin, glm::vec3 dir, Rng& rng, PathStats& stats) const;

 private:
  struct Surface {
    glm::vec3 position;
    glm::vec3 normal;     // shading normal, facing the incoming ray
    glm::vec3 geometric;  // geometric normal, facing the incoming ray
    Brdf brdf;
    glm::vec3 wo;        // towards where the ray came from
    glm::vec3 emission;  // emitted towards the incoming ray (one-sided)

    // The BRDF times cos at the shading normal, and its sampling pdf, for
    // light arriving from world direction wi.
    glm::vec3 FCos(const glm::vec3& wi) const;
    float Pdf(const glm::vec3& wi) const;
    glm::vec3 ToLocal(const glm::vec3& w) const;
    glm::vec3 tangent, bitangent;  // with `normal`, the BRDF's local frame
  };
  // Emitted radiance of emitter triangle `t` at barycentrics (u, v), front side.
  glm::vec3 Emission(const Triangle& t, float u, float v) const;
  Surface Shade(const Hit& hit, const glm::vec3& dir) const;
  glm::vec3 Environment(const glm::vec3& dir) const;
  // Next-event estimation at `s`; `wo` is the direction back to the viewer.
  glm::vec3 SampleAreaLights(const Surface& s, Rng& rng, PathStats& stats) const;
  glm::vec3 SamplePunctualLights(const Surface& s, PathStats& stats) const;
  glm::vec3 SampleEnvironment(const Surface& s, Rng& rng, PathStats& stats) const;
  // Solid-angle pdf of hitting emitter triangle `t` at distance d with
  // cosine cos_y through area-light sampling.
  float AreaLightPdf(const Triangle& t, float distance, float cos_y) const;
  glm::vec3 Offset(const Surface& s, const glm::vec3& towards) const;

  const SceneState& state_;
  const SceneBvh& bvh_;
  const EnvironmentLight* env_;  // null or empty: no environment
  IntegratorSettings settings_;
};

}  // namespace gistream::pathtrace
