// Light transport is linear in the emission: when every punctual light,
// emissive material and the environment changed by one common factor k
// since a GI solution was computed (a dimmer: same colours, positions,
// directions, cones and environment rotation; geometry and albedo
// unchanged), the solution's indirect light is k times the solved one.
// GI solvers then skip their view-independent stages and scale the
// indirect term at display (shaders/render/shade_surface.glsl,
// uIndirectScale); any other light change needs a new solve. Direct light
// is always the current one (render/direct_lighting.h redraws no shadow
// map for such a change).
#pragma once

#include <optional>
#include <vector>

#include "scene/state/scene_state.h"
#include "scene/updates.h"

namespace gistream {

class EmissionScale {
 public:
  // The GI state now reflects `state`'s lights (scale 1).
  void Solved(const SceneState& state);
  // Forget the solved lights (the next change needs a solve).
  void Reset() { solved_ = false; }

  // k when `changes` touched lights, emission or the environment (nothing
  // else) and the scene's lights are the solved ones times k (k >= 0);
  // nullopt when a new solve is needed or there is no light change.
  std::optional<float> Factor(const SceneState& state, ChangeMask changes) const;

 private:
  // Radiometric values (colour x intensity per light, emission per
  // material, environment intensity) that must scale together, and the
  // geometric ones that must not change.
  static void Signature(const SceneState& state, std::vector<float>& radiometry,
                        std::vector<float>& geometry);

  bool solved_ = false;
  std::vector<float> radiometry_, geometry_;
};

}  // namespace gistream
