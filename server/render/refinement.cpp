#include "render/refinement.h"

#include <cmath>

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

int Refinement::Next(const Key& key, uint32_t target) {
  if (!(key == key_) || !key.solution_final || target <= 1 || samples_ == 0) {
    key_ = key;
    samples_ = 0;
    return 0;
  }
  return samples_ >= target ? -1 : int(samples_);
}

glm::vec2 Refinement::Jitter(uint32_t k) {
  return {Rotated(RadicalInverse(k, 2)), Rotated(RadicalInverse(k, 3))};
}

}  // namespace gistream
