// Sampling glTF animations (glTF 2.0 3.11 "Animations" and Appendix C
// "Animation Sampler Interpolation Modes"): a pure function of the
// imported data and a time, giving the animated nodes' TRS and morph
// weights. Nothing here touches a session or the renderer.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene/scene.h"

namespace gistream {

// What the animation sets on one node; unset members keep the node's own.
struct NodeOverride {
  int node = -1;
  std::optional<glm::vec3> translation = {};
  std::optional<glm::quat> rotation = {};  // unit length
  std::optional<glm::vec3> scale = {};
  std::vector<float> weights = {};  // empty: not animated
};

enum class AnimationTime {
  kClamp,  // before start: the first keys; after end: the last keys
  kLoop,   // t wraps into [start, end)
};

// One sampler at time t (seconds, on the sampler's own keys: clamped to its
// first and last key). Returns `components` floats; rotations (4
// components, x y z w) are slerped on the shortest arc (LINEAR) and
// renormalised (CUBICSPLINE).
std::vector<float> SampleSampler(const AnimationSampler& sampler, AnimationPath path, float t);

// The whole animation at time t: one override per animated node, in order
// of first appearance among the channels. With kLoop, t is first wrapped
// into [animation.start, animation.end); an animation whose start equals
// its end is constant.
std::vector<NodeOverride> SampleAnimation(const Animation& animation, float t,
                                          AnimationTime mode = AnimationTime::kClamp);

// Writes the overrides into `nodes` (a copy of Scene::nodes).
void ApplyOverrides(std::span<const NodeOverride> overrides, std::vector<Node>* nodes);

// Shortest-arc spherical interpolation of unit quaternions, s in [0, 1].
glm::quat SlerpShortest(const glm::quat& a, const glm::quat& b, float s);

}  // namespace gistream
