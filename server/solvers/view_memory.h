// A solver's view-dependent memory (what its EstimateMemory cannot know:
// the size of the views it will shade), reserved through
// SolverContext::reserve before it is allocated, so that the server's
// memory budget and the tenant's gpu_bytes quota cover it too. A refusal is
// RESOURCE_EXHAUSTED naming `what` and the budget or quota.
#pragma once

#include <cstdint>
#include <string>

#include "solvers/solver.h"

namespace gistream {

// Reserves `cpu_bytes` + `gpu_bytes` through `ctx.reserve` (an empty charge
// when the context counts nothing).
absl::StatusOr<MemoryCharge> ReserveViewMemory(const SolverContext& ctx, uint64_t cpu_bytes,
                                               uint64_t gpu_bytes, const std::string& what);

// Scratch a solver resizes to the view it shades (render targets, an upload
// buffer), one for all its views: holds the reservation of the largest size
// it has had, growing it before the scratch grows.
class ViewScratch {
 public:
  absl::Status Fit(const SolverContext& ctx, uint64_t cpu_bytes, uint64_t gpu_bytes,
                   const std::string& what);
  uint64_t bytes() const { return charge_.bytes(); }

 private:
  MemoryCharge charge_;
  uint64_t cpu_ = 0;
  uint64_t gpu_ = 0;
};

}  // namespace gistream
