// Refinement of a still view (issue 27): while camera, scene version and
// solver solution stay the same, each frame shades more sub-pixel jittered
// samples (G-buffer and the solver's final pass; as many as the frame's
// budget allows, one in a frame that applied an update) and the view shows
// their mean: a box pixel filter, like pathtrace's, converging to the
// box-filtered picture, edges and emitters anti-aliased. The first sample
// is the pixel centre, so a frame of one sample is the picture an
// unrefined view shows. A change resets the samples; once `target` samples
// are in, the picture is complete and the engine shades nothing more.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace gistream {

class Refinement {
 public:
  // What the accumulated samples show; any difference invalidates them.
  struct Key {
    uint64_t scene_version = 0;
    uint64_t camera_version = 0;   // counts the view's camera changes
    const void* solver = nullptr;  // the solver instance shading the view
    uint32_t width = 0, height = 0;
    // The solver's view-independent solution is final (UpdateComplete):
    // while it is not, each frame may show a newer one and is not refined.
    bool solution_final = false;
    bool operator==(const Key&) const = default;
  };

  // The sample this frame shades, from 0, or -1 when the picture is
  // complete (the accumulation holds `target` samples of this key).
  // Restarts at 0 on another key (a camera change, a new scene version,
  // another solver or size), a solution that is not final, or target <= 1.
  int Next(const Key& key, uint32_t target);
  // Another sample of the same key in the same frame (the solver's solution
  // cannot change within it, final or not), or -1 once `target` are in.
  int Continue(uint32_t target) const { return samples_ >= target ? -1 : int(samples_); }
  // The sample Next or Continue returned was accumulated.
  void Added() { samples_ += 1; }
  // Samples in the accumulation (the picture shown: 1 when not refining).
  uint32_t samples() const { return samples_; }
  void Reset() { samples_ = 0; }

  // Sample k's offset from the pixel centre in pixels, in [-0.5, 0.5)^2:
  // the Halton (2, 3) sequence rotated by half a pixel (Cranley-Patterson),
  // so sample 0 is the centre and any prefix is well stratified.
  static glm::vec2 Jitter(uint32_t k);

 private:
  Key key_{};
  uint32_t samples_ = 0;
};

}  // namespace gistream
