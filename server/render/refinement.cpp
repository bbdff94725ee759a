#include "render/refinement.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gistream {
namespace {

// Radical inverse of k in `base`: the Halton sequence's k-th coordinate.
float RadicalInverse(uint32_t k, uint32_t base) {
  double inv = 1.0 / base, f = inv, r = 0.0;
  while (k > 0) {
    r += f * double(k % base);
    k /= base;
    f *= inv;
  }
  return float(r);
}

float Rotated(float u) {
  const float v = u + 0.5f;
  return (v >= 1.0f ? v - 1.0f : v) - 0.5f;
}

}  // namespace

std::optional<Refinement::Sample> Refinement::Next(const Key& key, uint32_t target,
                                                   uint32_t history, bool carry,
                                                   uint32_t reproject) {
  const bool same_view = samples_ > 0 && key.SameView(key_);
  // Small steps of the solution shown go on with an incomplete picture
  // (they add up to less than the solver's tolerance; a complete one is
  // shaded again).
  const bool same =
      (key == key_ && key.Steady()) || (same_view && samples_ < target && key.StepsFrom(key_));
  if (same) key_ = key;
  if (target <= 1 || !same_view || (!same && history == 0)) {
    // A camera move with a picture shown (same size and solver): that
    // picture, reprojected, is the history of the new view's first frames.
    const bool moved = samples_ > 0 && key.solver == key_.solver && key.width == key_.width &&
                       key.height == key_.height && key.camera_version != key_.camera_version;
    // It needs the shown picture's centre samples (the history target
    // holds them, as for the carry), so not with a history.
    reproject_ = target > 1 && moved && history == 0 ? reproject : 0;
    // The view changed (or nothing was shown yet, or no history is kept):
    // the samples restart at the pixel centre; under the same view the
    // anti-aliasing of the last complete picture is carried over.
    carry_on_ = target > 1 && carry && history == 0;
    carrying_ = carry_on_ && same_view && carry_valid_;
    if (!(carry_on_ && same_view)) carry_valid_ = false;
    key_ = key;
    samples_ = 0;
    accumulation_ = 0;
    history_ = 0;
    history_invalid_ = {};
    carry_captured_ = false;
    Sample first{0, 0, false};
    first.carry = carrying_;
    // Only a carried or reprojected picture needs its centre.
    first.centre = carry_on_ || (target > 1 && history == 0 && reproject > 0);
    first.reproject = reproject_ > 0;
    return first;
  }
  if (!same) {
    // Only what the view shows changed: the picture shown is the history.
    reproject_ = 0;
    key_ = key;
    samples_ = 0;
    accumulation_ += 1;
    history_ = history;
    history_invalid_ = {};
    carrying_ = false;
    carry_valid_ = false;  // the history target holds the history now
    return Sample{0, accumulation_ % target, true};
  }
  return Continue(target);
}

std::optional<Refinement::Sample> Refinement::Continue(uint32_t target) const {
  if (samples_ >= target) return std::nullopt;
  return Sample{samples_, (samples_ + accumulation_) % std::max(target, 1u), false};
}

float Refinement::HistoryWeight(uint32_t target) const {
  if (history_ == 0 || target < 2 || samples_ >= target) return 0.0f;
  // `history_` at one sample, 0 at `target`.
  return float(history_) * float(target - samples_) / float(target - 1);
}

float Refinement::CarryWeight(uint32_t target) const {
  if (!carrying_ || target < 2 || samples_ >= target) return 0.0f;
  // The samples the accumulation lacks, and never less than those it has
  // until it is complete: the first frame is mostly the carried picture,
  // from half way the carried picture and the new mean count alike, a
  // complete picture is its own mean. (Where nothing changed the shader
  // shows the carried picture whole; this weight is the changed pixels'.)
  // A prefix of the sample sequence is not a complete picture's equal on
  // an edge (an emitter's outline: a still 128x128 box reads 1.9e-3 at
  // 8-13 samples, 1.0e-3 at 16), so with a weight of target - n the frames
  // 9-15 samples after a change were worse than those before
  // (antiradiance's object workload, blending every pixel: 2.55e-3 at 8,
  // 3.09e-3 at 14; with this weight 2.53e-3 and 2.94e-3). Weighting it by
  // (target - n) target / n, nearer the carried picture early on, measured
  // worse there (3.2e-3 against 2.9e-3 at n = 3).
  return float(std::max(target - samples_, samples_));
}

float Refinement::ReprojectWeight(uint32_t target) const {
  if (reproject_ == 0 || target < 2 || samples_ >= target) return 0.0f;
  // `reproject_` at one sample, 0 at `target` (as HistoryWeight).
  return float(reproject_) * float(target - samples_) / float(target - 1);
}

bool Refinement::CaptureCarry(uint32_t target) {
  if (!carry_on_ || target < 2 || samples_ < target || accumulation_ != 0 || carry_captured_) {
    return false;
  }
  carry_captured_ = true;
  carry_valid_ = true;
  return true;
}

Refinement::PixelBox MovedPixels(const ViewCamera& camera, const Bounds& moved) {
  if (moved.empty()) return {};
  const glm::ivec2 size(int(camera.width), int(camera.height));
  const Refinement::PixelBox all{glm::ivec2(0), size};
  // Pixel centres (no jitter) of the box's corners; a corner at or behind
  // the eye's plane could be anywhere on screen: all of it.
  ViewCamera centred = camera;
  centred.jitter = glm::vec2(0.0f);
  const glm::mat4 view = centred.View();
  const glm::mat4 proj = centred.Projection();
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 corner((i & 1) ? moved.max.x : moved.min.x, (i & 2) ? moved.max.y : moved.min.y,
                           (i & 4) ? moved.max.z : moved.min.z);
    const glm::vec4 eye = view * glm::vec4(corner, 1.0f);
    if (!(eye.z < -1e-6f * glm::length(glm::vec3(eye)))) return all;
    const glm::vec4 clip = proj * eye;
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    if (!std::isfinite(ndc.x) || !std::isfinite(ndc.y)) return all;
    const glm::vec2 pixel = (ndc * 0.5f + 0.5f) * glm::vec2(size);
    lo = glm::min(lo, pixel);
    hi = glm::max(hi, pixel);
  }
  // Widened by the show pass's 3x3 neighbourhood and a pixel of jitter.
  const glm::vec2 max_pixel(size);
  const glm::vec2 a = glm::clamp(glm::floor(lo) - 2.0f, glm::vec2(0.0f), max_pixel);
  const glm::vec2 b = glm::clamp(glm::ceil(hi) + 2.0f, glm::vec2(0.0f), max_pixel);
  return {glm::ivec2(a), glm::ivec2(b)};
}

glm::vec2 Refinement::Jitter(uint32_t k) {
  return {Rotated(RadicalInverse(k, 2)), Rotated(RadicalInverse(k, 3))};
}

}  // namespace gistream
