// A minimal parallel-for for the antiradiance CPU stages: chunks of
// indices handed out from an atomic counter, one std::thread per hardware
// thread. (Same shape as implicit_visibility's hierarchy/parallel.h; to be
// merged into it once that is on main.)
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace gistream::antiradiance {

inline unsigned WorkerCount() { return std::max(1u, std::thread::hardware_concurrency()); }

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
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < workers; ++t) pool.emplace_back(run);
  run();
  for (std::thread& t : pool) t.join();
}

}  // namespace gistream::antiradiance
