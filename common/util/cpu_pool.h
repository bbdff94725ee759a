// The one CPU pool of the process. Every multi-threaded CPU stage (linking,
// transport, VPL tracing, path tracing, BVH work) runs its loops here
// instead of starting threads of its own, so the process never runs more
// threads than its CPU share: the pool is sized once from the CPU affinity
// mask and the cgroup CPU quota (a container's `--cpus`), or from
// `gistreamd --cpu-threads N`.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace gistream {

// min(CPUs in the affinity mask, ceil(cgroup quota / period)), at least 1.
unsigned DefaultCpuThreads();

// The quota part alone: ceil(quota / period) from cgroup v2's cpu.max or
// v1's cpu.cfs_quota_us / cpu.cfs_period_us under `cgroup_root`; 0 when
// there is no limit. Exposed for tests.
unsigned CgroupCpuLimit(const std::string& cgroup_root = "/sys/fs/cgroup");

class CpuPool {
 public:
  // `threads` threads of execution run a ParallelFor: threads - 1 workers
  // plus the calling thread.
  explicit CpuPool(unsigned threads);
  ~CpuPool();
  CpuPool(const CpuPool&) = delete;
  CpuPool& operator=(const CpuPool&) = delete;

  // The process's pool. Configure (before first use; 0 = DefaultCpuThreads)
  // fixes its size; without it the default is used.
  static CpuPool& Get();
  static void Configure(unsigned threads);

  unsigned threads() const { return unsigned(workers_.size()) + 1; }

  // Calls fn(i) for every i in [0, n), `chunk` consecutive indices at a
  // time (dynamic scheduling), on the workers and the calling thread;
  // returns when all are done. Safe to call from several threads at once
  // (their loops share the workers). Under a cancelled stop token
  // (util/cancellation.h) the indices not started are skipped.
  void ParallelFor(size_t n, size_t chunk, const std::function<void(size_t)>& fn);

  // Runs `task` on a worker (on the calling thread when the pool has no
  // workers) and returns at once; the future is ready when it has run. The
  // task may use ParallelFor. Whoever owns what the task touches waits for
  // the future before destroying it.
  std::shared_future<void> Async(std::function<void()> task);

 private:
  struct Job;
  void WorkerLoop();
  static void Drain(Job& job);

  std::mutex mutex_;
  std::condition_variable work_cv_;  // workers: a job arrived or stop
  std::condition_variable done_cv_;  // callers: a worker left a job
  std::deque<std::shared_ptr<Job>> jobs_;
  bool stop_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace gistream
