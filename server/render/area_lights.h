// Emissive surfaces as area lights: world-space emitter triangles and a
// stratified set of sample points on them, distributed by emitted power.
// Each sample is an oriented disc of area A_i = 1 / (N pdf(y_i)), so that
// sum_i L_i A_i G(x, y_i) / N-style estimates converge to the emitter's true
// direct light as N grows.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/state/scene_state.h"

namespace gistream {

struct EmitterTriangle {
  glm::vec3 p0, p1, p2;
  glm::vec3 normal;    // unit, the emitting side
  glm::vec3 radiance;  // nits
  float area = 0.0f;
};

struct EmitterSample {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec3 radiance;
  float area = 0.0f;  // A_i = 1 / (N pdf(y_i))
  int triangle = -1;  // the emitter triangle it lies on
};

// Emissive triangles of the current state (degenerate ones dropped). A
// triangle of a doubleSided material is listed twice, once per face (normal
// flipped, winding reversed): both faces emit.
std::vector<EmitterTriangle> CollectEmitters(const SceneState& state);

// Total emitted power, sum over triangles of pi * L * A (watts in glTF's
// photometric-as-radiometric convention).
glm::vec3 EmittedPower(const std::vector<EmitterTriangle>& emitters);

// `count` stratified samples (Hammersley points mapped through the
// power-weighted triangle CDF); deterministic.
std::vector<EmitterSample> SampleEmitters(const std::vector<EmitterTriangle>& emitters, int count);

}  // namespace gistream
