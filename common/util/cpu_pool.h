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
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace gistream {

// The tenant whose work the calling thread does ("" when none): loops and
// Async tasks started under a CpuTenantScope are that tenant's, and so are
// the loops those tasks start. The pool shares its workers between tenants
// (issue 30, item 3): a free worker takes a job of the tenant with the
// fewest workers busy on its jobs, then the least CPU time in the pool,
// then the oldest; and it comes back to choose after each slice of about
// kCpuSliceMs (between chunks), so one tenant's queue of background solves
// or its long loop no longer holds another tenant's work behind it.
class CpuTenantScope {
 public:
  explicit CpuTenantScope(std::string tenant);
  ~CpuTenantScope();
  CpuTenantScope(const CpuTenantScope&) = delete;
  CpuTenantScope& operator=(const CpuTenantScope&) = delete;

 private:
  std::string previous_;
};
const std::string& CurrentCpuTenant();

// A worker's slice of a job before it chooses again.
inline constexpr double kCpuSliceMs = 5.0;

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

  // A tenant's share so far: workers busy on its jobs now, and the CPU
  // milliseconds its jobs have run in the pool (workers and callers).
  struct TenantShare {
    int busy = 0;
    double cpu_ms = 0.0;
  };
  // The shares of the tenants with work queued or running (for tests).
  std::map<std::string, TenantShare> Shares();

 private:
  struct Job;
  void WorkerLoop();
  // Runs job's chunks until it is exhausted or, when slice_ms > 0, that
  // long has passed; returns the milliseconds it ran.
  static double Drain(Job& job, double slice_ms);
  // The job a free worker takes (null: none left), dropping exhausted
  // ones and the shares of tenants with nothing queued or running.
  std::shared_ptr<Job> PickLocked();
  TenantShare& ShareLocked(const std::string& tenant);
  // Drops the shares of tenants with nothing queued or running.
  void ForgetIdleLocked();

  std::mutex mutex_;
  std::condition_variable work_cv_;  // workers: a job arrived or stop
  std::condition_variable done_cv_;  // callers: a worker left a job
  std::deque<std::shared_ptr<Job>> jobs_;
  std::map<std::string, TenantShare> shares_;
  bool stop_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace gistream
