// A deforming scene built in code for the deformation tests: a segmented
// tube (rings along +Y) skinned to two joints, the upper joint a child of
// the lower, with one morph target (a radial bulge) and one animation that
// bends the upper joint about Z (LINEAR, 0 to 2 s).
#pragma once

#include "scene/scene.h"
#include "scene/updates.h"

namespace gistream::testing {

struct DeformingTube {
  static constexpr int kTubeNode = 0;
  static constexpr int kRootJoint = 1;
  static constexpr int kBendJoint = 2;
  static constexpr float kBendAngle = 1.2f;  // radians at the animation's end
};

// `rings` rings of `sides` vertices, `length` tall, radius `radius`; the
// tube's node is placed at `origin`.
Scene MakeDeformingTube(int rings = 9, int sides = 12, float length = 2.0f, float radius = 0.25f,
                        glm::vec3 origin = glm::vec3(0.0f));

// Update `seq`: the scene's animation 0 sought to `seconds`, paused.
inline Update SeekAnimation(uint64_t seq, float seconds) {
  AnimationUpdate a;
  a.animation = 0;
  a.playing = false;
  a.time = seconds;
  return {seq, a};
}

}  // namespace gistream::testing
