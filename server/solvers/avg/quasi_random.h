// The quasi-random numbers that drive VPL tracing (paper, Sec. III-B: "a
// quasi-random sequence to ensure the same distribution of VPLs between
// frames"). A Halton sequence with fixed random digit permutations per
// dimension (scrambling breaks the correlation of the high-base
// dimensions); the permutations are seeded once, so path i gets the same
// numbers every frame and a still scene does not flicker.
#pragma once

#include <cstdint>
#include <vector>

namespace gistream::avg {

class ScrambledHalton {
 public:
  static constexpr int kMaxDimensions = 48;

  // Sample `index`, dimension `dim` (< kMaxDimensions), in [0, 1).
  float Get(uint64_t index, int dim) const;

  static const ScrambledHalton& Instance();

 private:
  ScrambledHalton();
  // perms_[dim] holds kDigits permutations of 0..base-1, one per digit.
  std::vector<std::vector<uint16_t>> perms_;
  std::vector<int> digits_;
};

}  // namespace gistream::avg
