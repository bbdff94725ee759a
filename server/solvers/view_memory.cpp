#include "solvers/view_memory.h"

#include <algorithm>

namespace gistream {

absl::StatusOr<MemoryCharge> ReserveViewMemory(const SolverContext& ctx, uint64_t cpu_bytes,
                                               uint64_t gpu_bytes, const std::string& what) {
  if (!ctx.reserve) return MemoryCharge();
  return ctx.reserve(cpu_bytes, gpu_bytes, what);
}

absl::Status ViewScratch::Fit(const SolverContext& ctx, uint64_t cpu_bytes, uint64_t gpu_bytes,
                              const std::string& what) {
  if (cpu_bytes <= cpu_ && gpu_bytes <= gpu_) return absl::OkStatus();
  const uint64_t more_cpu = cpu_bytes > cpu_ ? cpu_bytes - cpu_ : 0;
  const uint64_t more_gpu = gpu_bytes > gpu_ ? gpu_bytes - gpu_ : 0;
  GS_ASSIGN_OR_RETURN(MemoryCharge more, ReserveViewMemory(ctx, more_cpu, more_gpu, what));
  charge_.Merge(std::move(more));
  cpu_ = std::max(cpu_, cpu_bytes);
  gpu_ = std::max(gpu_, gpu_bytes);
  return absl::OkStatus();
}

}  // namespace gistream
