// A minimal parallel-for for the solvers' CPU stages (hierarchy linking,
// antiradiance transport, ...): indices handed out in chunks from an atomic counter (dynamic scheduling,
// since link work per top-level pair varies by orders of magnitude), one
// std::thread per hardware thread, joined before returning.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace gistream {

inline unsigned WorkerCount() { return std::max(1u, std::thread::hardware_concurrency()); }

// Calls fn(i) for every i in [0, n), `chunk` consecutive indices at a time.
template <typename Fn>
void ParallelFor(size_t n, size_t chunk, Fn&& fn) {
  if (n == 0) return;
  chunk = std::max<size_t>(chunk, 1);
  const unsigned workers = unsigned(std::min<size_t>(WorkerCount(), (n + chunk - 1) / chunk));
  std::atomic<size_t> next{0};
  auto run = [&] {
    for (;;) {
      const size_t begin = next.fetch_add(chunk);
      if (begin >= n) return;
      const size_t end = std::min(n, begin + chunk);
      for (size_t i = begin; i < end; ++i) fn(i);
    }
  };
  if (workers <= 1) {
    run();
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (unsigned t = 1; t < workers; ++t) pool.emplace_back(run);
  run();
  for (std::thread& t : pool) t.join();
}

}  // namespace gistream
