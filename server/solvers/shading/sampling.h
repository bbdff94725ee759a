// Random numbers and sampling warps for the reference path tracer. Every
// sample's generator is seeded from (seed, pixel, sample index), so images
// are identical for a given seed whatever the thread schedule.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace gistream::shading {

// PCG32 (O'Neill), XSH RR variant.
class Rng {
 public:
  Rng(uint64_t seed, uint64_t stream) {
    inc_ = (stream << 1u) | 1u;
    Next();
    state_ += seed;
    Next();
  }
  uint32_t Next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  // Uniform in [0, 1).
  float Uniform() { return float(Next() >> 8) * 0x1p-24f; }

 private:
  uint64_t state_ = 0;
  uint64_t inc_ = 0;
};

inline uint64_t Mix64(uint64_t x) {
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdull;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ull;
  x ^= x >> 33;
  return x;
}

// Orthonormal basis around unit n (Duff et al. 2017).
inline void Basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction around unit n; pdf = cos(theta) / pi.
inline glm::vec3 SampleCosine(const glm::vec3& n, float u1, float u2) {
  const float r = std::sqrt(u1);
  const float phi = 2.0f * 3.14159265358979f * u2;
  glm::vec3 t, b;
  Basis(n, t, b);
  const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
  return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + z * n);
}

inline float Luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// Power heuristic (beta = 2) for multiple importance sampling (Veach 1997).
inline float PowerHeuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

}  // namespace gistream::shading
