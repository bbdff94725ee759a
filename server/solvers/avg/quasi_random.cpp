#include "solvers/avg/quasi_random.h"

#include <algorithm>
#include <numeric>
#include <random>

#include "util/status.h"

namespace gistream::avg {
namespace {

constexpr int kPrimes[ScrambledHalton::kMaxDimensions] = {
    2,   3,   5,   7,   11,  13,  17,  19,  23,  29,  31,  37,  41,  43,  47,  53,
    59,  61,  67,  71,  73,  79,  83,  89,  97,  101, 103, 107, 109, 113, 127, 131,
    137, 139, 149, 151, 157, 163, 167, 173, 179, 181, 191, 193, 197, 199, 211, 223};

}  // namespace

ScrambledHalton::ScrambledHalton() {
  std::mt19937 rng(0x9e3779b9u);  // fixed: the same sequence in every process
  perms_.resize(kMaxDimensions);
  digits_.resize(kMaxDimensions);
  for (int d = 0; d < kMaxDimensions; ++d) {
    const int base = kPrimes[d];
    // Enough digits to resolve 2^32 indices.
    int digits = 0;
    for (double span = 1.0; span < 4294967296.0; span *= base) ++digits;
    digits_[size_t(d)] = digits;
    std::vector<uint16_t>& p = perms_[size_t(d)];
    p.resize(size_t(digits) * size_t(base));
    for (int k = 0; k < digits; ++k) {
      auto first = p.begin() + k * base;
      std::iota(first, first + base, uint16_t(0));
      // Dimension 0 (base 2) stays unscrambled: it picks lights and must
      // stay a stratified van der Corput sequence for every prefix.
      if (d > 0) std::shuffle(first, first + base, rng);
    }
  }
}

const ScrambledHalton& ScrambledHalton::Instance() {
  static const ScrambledHalton kInstance;
  return kInstance;
}

float ScrambledHalton::Get(uint64_t index, int dim) const {
  GS_CHECK(dim >= 0 && dim < kMaxDimensions);
  const int base = kPrimes[dim];
  const std::vector<uint16_t>& p = perms_[size_t(dim)];
  double inv_base = 1.0 / base, scale = inv_base, value = 0.0;
  for (int k = 0; k < digits_[size_t(dim)]; ++k) {
    const uint64_t digit = index % uint64_t(base);
    index /= uint64_t(base);
    value += double(p[size_t(k) * size_t(base) + digit]) * scale;
    scale *= inv_base;
  }
  // The permuted trailing digits can round the sum up to 1.
  return std::min(float(value), 0x1.fffffep-1f);
}

}  // namespace gistream::avg
