#include "solvers/emission_scale.h"

#include <algorithm>
#include <cmath>

namespace gistream {
namespace {

// Relative tolerance of "the same factor": float rounding of products of
// validated, finite inputs stays far below it.
constexpr float kTolerance = 1e-5f;

}  // namespace

void EmissionScale::Signature(const SceneState& state, std::vector<float>& radiometry,
                              std::vector<float>& geometry) {
  radiometry.clear();
  geometry.clear();
  for (const LightInstance& l : state.lights()) {
    const glm::vec3 power = l.light.color * l.light.intensity;
    radiometry.insert(radiometry.end(), {power.r, power.g, power.b});
    geometry.insert(geometry.end(), {l.position.x, l.position.y, l.position.z, l.direction.x,
                                     l.direction.y, l.direction.z, l.light.inner_cone_angle,
                                     l.light.outer_cone_angle, float(int(l.light.type))});
  }
  for (const Material& m : state.materials()) {
    const glm::vec3 e = m.emission();
    radiometry.insert(radiometry.end(), {e.r, e.g, e.b});
  }
  if (state.scene().environment) {
    radiometry.push_back(state.environment_intensity());
    geometry.push_back(state.environment_rotation());
  }
}

void EmissionScale::Solved(const SceneState& state) {
  Signature(state, radiometry_, geometry_);
  solved_ = true;
}

std::optional<float> EmissionScale::Factor(const SceneState& state, ChangeMask changes) const {
  if (!solved_) return std::nullopt;
  // Only a change of lights (and nothing else) can be a pure scaling.
  constexpr ChangeMask kLightKinds = kChangeLights | kChangeEmission | kChangeEnvironment;
  if (!(changes & kLightKinds) || (changes & ~kLightKinds)) return std::nullopt;
  std::vector<float> radiometry, geometry;
  Signature(state, radiometry, geometry);
  if (geometry != geometry_ || radiometry.size() != radiometry_.size()) return std::nullopt;
  // k from the largest solved value, then every value must be k times its
  // solved one (zeros stay zero).
  size_t ref = 0;
  for (size_t i = 1; i < radiometry_.size(); ++i) {
    if (radiometry_[i] > radiometry_[ref]) ref = i;
  }
  if (radiometry_.empty() || !(radiometry_[ref] > 0.0f)) return std::nullopt;
  const float k = radiometry[ref] / radiometry_[ref];
  if (!std::isfinite(k) || k < 0.0f) return std::nullopt;
  for (size_t i = 0; i < radiometry_.size(); ++i) {
    const float expected = k * radiometry_[i];
    if (std::fabs(radiometry[i] - expected) >
        kTolerance * std::max(std::fabs(expected), radiometry[ref])) {
      return std::nullopt;
    }
  }
  return k;
}

}  // namespace gistream
