// Refinement of a view (issue 27): while camera, scene version and solver
// solution stay the same, each frame shades more sub-pixel jittered samples
// (G-buffer and the solver's final pass; as many as the frame's budget
// allows, one in a frame that applied an update) and the view shows their
// mean: a box pixel filter, like pathtrace's, converging to the
// box-filtered picture, edges and emitters anti-aliased. The first sample
// is the pixel centre, so a frame of one sample is the picture an
// unrefined view shows. Once `target` samples are in, the picture is
// complete and the engine shades nothing more.
//
// A solver whose update spreads over frames may count what it shows
// (Solver::Shown, Key::shown_changes and shown_steps): the picture is then
// refined while the update goes on, across the solver's small steps while
// it is incomplete, and restarts on its changes and when the update ends.
//
// What a change invalidates decides what is kept:
// - The view (size, solver instance): nothing. The samples restart at the
//   pixel centre.
// - The camera (reprojection, the default, EngineOptions::
//   refine_reproject): the samples restart at the pixel centre, and the
//   picture shown before the move is kept and reprojected at the weight
//   of `reproject` samples, fading out as the new samples come in: each
//   pixel's centre surface (from its centre sample's distance) is looked
//   up where the previous camera saw it, bilinearly over the texels whose
//   centres saw that surface at that distance (within 2 %; an emitter
//   never stands for what lies beside it), and clipped to the new samples'
//   3x3 neighbourhood; a pixel the move uncovered shows its new samples.
//   While the camera moves, every frame is the new centres plus the last
//   frame reprojected: temporal anti-aliasing across camera moves.
// - Only what the view shows (a new scene version, a solution still being
//   updated), the camera unchanged: the samples restart, but the picture
//   shown so far is kept as history, with the weight of `history` samples,
//   and fades out linearly as the new samples come in; it is gone once
//   `target` samples are in, so a complete picture is the mean of its own
//   samples only. Where the history no longer shows
//   the scene it is not used: within the screen box of what moved (old and
//   new place), and elsewhere it is clamped to the range of the new
//   samples' 3x3 neighbourhood (shaders/render/show_refined.frag.glsl), as
//   temporal anti-aliasing does. The jitter goes on across such changes
//   (Sample::jitter), so the frames of a moving scene seen by a still
//   camera anti-alias each other.
//   With a history weight of 0 (the engine's default, EngineOptions::
//   refine_history) such a change restarts the picture like a change of
//   the view, but carries the anti-aliasing over (below).
// - Carried anti-aliasing (the default): once a picture is complete, its
//   mean R and its pixel-centre sample C (sample 0) are kept. After a
//   change of what the view shows under the same camera, the new samples
//   restart at the pixel centre and the view shows (n x mean + m x H) /
//   (n + m), m = max(target - n, n), H = P + k (R - C): P the new pixel-centre
//   sample, k = P / C per channel (the lighting's change at the surface
//   the centre sees; 1 where C is dark against R - C, at most 4), clipped
//   to the new samples' 3x3 neighbourhood as the history is. R - C is what
//   the sub-pixel samples added to the pixel centre: the edges' and the
//   emitters' anti-aliasing, which a change of lighting scales but does not
//   move. Where geometry moved it is dropped: a pixel whose 3x3
//   neighbourhood's centres see another surface than the carried centres
//   did (their distance from the eye differs) shows its new samples; a
//   pixel whose neighbourhood's centres see what they saw (light within
//   2 %) shows H alone until the new picture is complete.
#pragma once

#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "render/camera.h"
#include "scene/scene.h"

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
    // while it is not, each frame may show a newer one and is not refined,
    // unless the solver counts what it shows (Solver::Shown): then the
    // picture is refined while its count of changes stays, and across its
    // small steps (each within the solver's tolerance) until it is complete
    // (a progressive update's every step restarted its pictures at one
    // sample a pixel for seconds).
    bool solution_final = false;
    std::optional<uint64_t> shown_changes;
    uint64_t shown_steps = 0;
    bool operator==(const Key&) const = default;
    // The same camera, size and solver: the pixels show the same surfaces
    // but for what moved.
    bool SameView(const Key& o) const {
      return camera_version == o.camera_version && solver == o.solver && width == o.width &&
             height == o.height;
    }
    // Equal keys show the same picture: the solution is final, or what the
    // solver shows is counted.
    bool Steady() const { return solution_final || shown_changes.has_value(); }
    // What `o` showed and this key shows differ by the solver's small steps
    // alone.
    bool StepsFrom(const Key& o) const {
      return SameView(o) && scene_version == o.scene_version && shown_changes &&
             shown_changes == o.shown_changes && solution_final == o.solution_final;
    }
  };

  struct Sample {
    uint32_t index = 0;  // in the accumulation: 0 starts it (a copy)
    // Its sub-pixel offset is Jitter(jitter): (index + a) mod target for
    // the a-th accumulation since the view last changed. An accumulation
    // thus shades the same `target` offsets as a fresh view's (0, the pixel
    // centre, first), so a complete picture does not depend on the changes
    // before it, and the frames of a change going on (sample 0 of
    // successive accumulations) step through those offsets, anti-aliasing
    // each other through the history.
    uint32_t jitter = 0;
    // The picture shown so far becomes the history (copy it before this
    // sample is shaded over it).
    bool keep_history = false;
    // The first sample after a change that carries the anti-aliasing over.
    bool carry = false;
    // The pixel-centre sample of an accumulation that can be carried or
    // reprojected (keep it, with its surface's distance, as C once shaded).
    bool centre = false;
    // The first sample after a camera move that reprojects the picture
    // shown before it (keep that picture before this sample is shaded).
    bool reproject = false;
  };

  // Pixels [min, max) (rows from the bottom, as GL's) where the history
  // shows what moved; empty when min >= max.
  struct PixelBox {
    glm::ivec2 min{0}, max{0};
  };

  // The sample this frame shades, or none when the picture is complete
  // (the accumulation holds `target` samples of this key). Restarts on
  // another key, or a solution that is not final; target <= 1 restarts
  // every frame and keeps no history. `history`: the weight, in samples, of
  // the picture kept after a change of what the view shows (0: none, the
  // change restarts it; 7: the picture right after it is (new sample + 7 x
  // history) / 8, an exponential moving average of alpha 1/8 while the
  // changes go on, every frame).
  // `carry`: carry the anti-aliasing over such a change when history is 0.
  // `reproject`: the weight, in samples, of the picture shown before a
  // camera move (same size and solver), reprojected into the new view
  // (0: none, the move restarts at the pixel centres); like `history`, an
  // exponential moving average while the camera moves, fading out as the
  // still view's samples come in.
  std::optional<Sample> Next(const Key& key, uint32_t target, uint32_t history, bool carry = true,
                             uint32_t reproject = 0);
  // Another sample of the same key in the same frame (the solver's solution
  // cannot change within it, final or not), or none once `target` are in.
  std::optional<Sample> Continue(uint32_t target) const;
  // The sample Next or Continue returned was accumulated.
  void Added() { samples_ += 1; }
  // Samples in the accumulation (1 when not refining).
  uint32_t samples() const { return samples_; }
  // The history's weight in the picture shown, in samples: `history` after
  // a change, falling linearly to 0 at `target` samples; 0 without history.
  float HistoryWeight(uint32_t target) const;
  // The carried picture's weight, in samples: max(target - n, n) while an
  // accumulation after a change carries the anti-aliasing over, else 0.
  float CarryWeight(uint32_t target) const;
  // The reprojected picture's weight, in samples: `reproject` after a
  // camera move, falling linearly to 0 at `target` samples; else 0.
  float ReprojectWeight(uint32_t target) const;
  // True once, when the accumulation that began at the pixel centre is
  // complete: its mean and centre sample become the carried pair (copy
  // them), valid until the view changes.
  bool CaptureCarry(uint32_t target);
  bool carry_valid() const { return carry_valid_; }
  // Where the history must not be used (set with keep_history's sample).
  void SetHistoryInvalid(const PixelBox& box) { history_invalid_ = box; }
  const PixelBox& history_invalid() const { return history_invalid_; }

  // Sample k's offset from the pixel centre in pixels, in [-0.5, 0.5)^2:
  // the Halton (2, 3) sequence rotated by half a pixel (Cranley-Patterson),
  // so sample 0 is the centre and any prefix is well stratified.
  static glm::vec2 Jitter(uint32_t k);

 private:
  Key key_{};
  uint32_t samples_ = 0;
  uint32_t accumulation_ = 0;  // accumulations since the view last changed
  uint32_t history_ = 0;       // the kept picture's weight at one sample
  uint32_t reproject_ = 0;     // the reprojected picture's weight at one sample
  PixelBox history_invalid_{};
  bool carry_on_ = false;        // carrying is asked for (no history)
  bool carry_valid_ = false;     // a complete picture's pair is kept
  bool carrying_ = false;        // this accumulation shows it
  bool carry_captured_ = false;  // this accumulation's pair was kept
};

// The pixels `camera` (without its jitter) sees of the world box `moved`
// (what moved since the history's picture, old and new place), widened by
// two pixels for the show pass's 3x3 neighbourhood and the jitter; all of
// the view when a corner is at or behind the eye's plane; empty for an
// empty box. For Refinement::SetHistoryInvalid.
Refinement::PixelBox MovedPixels(const ViewCamera& camera, const Bounds& moved);

}  // namespace gistream
