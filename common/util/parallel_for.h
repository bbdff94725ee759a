// The solvers' parallel-for (hierarchy linking, antiradiance transport, VPL
// tracing, path tracing, ...): indices handed out in chunks from an atomic
// counter (dynamic scheduling, since work per item varies by orders of
// magnitude) on the process's one CPU pool (util/cpu_pool.h), never on
// threads of its own.
#pragma once

#include <cstddef>
#include <functional>

#include "util/cpu_pool.h"

namespace gistream {

// Threads a ParallelFor runs on (the pool's size, --cpu-threads).
inline unsigned WorkerCount() { return CpuPool::Get().threads(); }

// Calls fn(i) for every i in [0, n), `chunk` consecutive indices at a time.
template <typename Fn>
void ParallelFor(size_t n, size_t chunk, Fn&& fn) {
  const std::function<void(size_t)> body = [&fn](size_t i) { fn(i); };
  CpuPool::Get().ParallelFor(n, chunk, body);
}

}  // namespace gistream
