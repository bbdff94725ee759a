#include "util/cpu_pool.h"

#include "util/cancellation.h"

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <string>

namespace gistream {
namespace {

std::mutex g_config_mutex;
unsigned g_configured = 0;
thread_local std::string t_tenant;

bool ReadNumbers(const std::string& path, std::string& first, std::string& second) {
  std::ifstream in(path);
  return bool(in >> first >> second);
}

bool ReadNumber(const std::string& path, std::string& value) {
  std::ifstream in(path);
  return bool(in >> value);
}

unsigned QuotaThreads(double quota, double period) {
  if (!(quota > 0.0) || !(period > 0.0)) return 0;
  return std::max(1u, unsigned(std::ceil(quota / period)));
}

}  // namespace

CpuTenantScope::CpuTenantScope(std::string tenant) : previous_(std::move(t_tenant)) {
  t_tenant = std::move(tenant);
}

CpuTenantScope::~CpuTenantScope() { t_tenant = std::move(previous_); }

const std::string& CurrentCpuTenant() { return t_tenant; }

unsigned CgroupCpuLimit(const std::string& root) {
  // cgroup v2: "max 100000" (no limit) or "200000 100000" (2 CPUs).
  std::string quota, period;
  if (ReadNumbers(root + "/cpu.max", quota, period)) {
    if (quota == "max") return 0;
    return QuotaThreads(std::atof(quota.c_str()), std::atof(period.c_str()));
  }
  // cgroup v1: a quota of -1 means no limit.
  if (ReadNumber(root + "/cpu/cpu.cfs_quota_us", quota) &&
      ReadNumber(root + "/cpu/cpu.cfs_period_us", period)) {
    return QuotaThreads(std::atof(quota.c_str()), std::atof(period.c_str()));
  }
  return 0;
}

unsigned DefaultCpuThreads() {
  unsigned cpus = std::max(1u, std::thread::hardware_concurrency());
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) {
    cpus = std::max(1, CPU_COUNT(&set));
  }
  const unsigned quota = CgroupCpuLimit();
  return quota > 0 ? std::min(cpus, quota) : cpus;
}

struct CpuPool::Job {
  size_t n = 0;
  size_t chunk = 1;
  const std::function<void(size_t)>* fn = nullptr;
  std::function<void(size_t)> owned;  // Async's task
  std::atomic<size_t> next{0};
  int active = 0;  // workers inside Drain (guarded by the pool's mutex)
  // The caller's (util/cancellation.h): its workers run under it, and no
  // index starts once it is cancelled.
  std::stop_token stop;
  std::string tenant;  // the caller's CurrentCpuTenant()
};

CpuPool::CpuPool(unsigned threads) {
  const unsigned workers = std::max(1u, threads) - 1;
  workers_.reserve(workers);
  for (unsigned i = 0; i < workers; ++i) workers_.emplace_back([this] { WorkerLoop(); });
}

CpuPool::~CpuPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  work_cv_.notify_all();
  for (std::thread& t : workers_) t.join();
}

CpuPool& CpuPool::Get() {
  static CpuPool pool([] {
    std::lock_guard lock(g_config_mutex);
    return g_configured > 0 ? g_configured : DefaultCpuThreads();
  }());
  return pool;
}

void CpuPool::Configure(unsigned threads) {
  std::lock_guard lock(g_config_mutex);
  g_configured = threads;
}

double CpuPool::Drain(Job& job, double slice_ms) {
  CancellationScope scope(job.stop);
  CpuTenantScope tenant(job.tenant);
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto elapsed_ms = [&] {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  for (;;) {
    if (job.stop.stop_requested()) {
      job.next.store(job.n);  // the rest is not started
      break;
    }
    const size_t begin = job.next.fetch_add(job.chunk);
    if (begin >= job.n) break;
    const size_t end = std::min(job.n, begin + job.chunk);
    for (size_t i = begin; i < end; ++i) (*job.fn)(i);
    if (slice_ms > 0.0 && elapsed_ms() >= slice_ms) break;
  }
  return elapsed_ms();
}

CpuPool::TenantShare& CpuPool::ShareLocked(const std::string& tenant) {
  auto it = shares_.find(tenant);
  if (it != shares_.end()) return it->second;
  // A tenant new to the pool starts level with the least-served one there,
  // not at zero: else it would take every worker until it caught up.
  TenantShare share;
  bool first = true;
  for (const auto& [name, s] : shares_) {
    share.cpu_ms = first ? s.cpu_ms : std::min(share.cpu_ms, s.cpu_ms);
    first = false;
  }
  return shares_.emplace(tenant, share).first->second;
}

std::shared_ptr<CpuPool::Job> CpuPool::PickLocked() {
  // Exhausted jobs leave the queue (their callers finish them).
  jobs_.erase(std::remove_if(jobs_.begin(), jobs_.end(),
                             [](const std::shared_ptr<Job>& j) { return j->next.load() >= j->n; }),
              jobs_.end());
  std::shared_ptr<Job> best;
  const TenantShare* best_share = nullptr;
  for (const std::shared_ptr<Job>& job : jobs_) {  // oldest first: ties keep arrival order
    const TenantShare& share = ShareLocked(job->tenant);
    if (!best || share.busy < best_share->busy ||
        (share.busy == best_share->busy && share.cpu_ms < best_share->cpu_ms)) {
      best = job;
      best_share = &share;
    }
  }
  ForgetIdleLocked();
  return best;
}

void CpuPool::ForgetIdleLocked() {
  for (auto it = shares_.begin(); it != shares_.end();) {
    const bool queued = std::any_of(jobs_.begin(), jobs_.end(), [&](const auto& j) {
      return j->tenant == it->first && j->next.load() < j->n;
    });
    it = !queued && it->second.busy == 0 ? shares_.erase(it) : std::next(it);
  }
}

std::map<std::string, CpuPool::TenantShare> CpuPool::Shares() {
  std::lock_guard lock(mutex_);
  return shares_;
}

void CpuPool::WorkerLoop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    work_cv_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
    if (stop_) return;
    const std::shared_ptr<Job> job = PickLocked();
    if (!job) continue;
    ++job->active;
    ++ShareLocked(job->tenant).busy;
    lock.unlock();
    const double ms = Drain(*job, kCpuSliceMs);
    lock.lock();
    --job->active;
    TenantShare& share = ShareLocked(job->tenant);
    --share.busy;
    share.cpu_ms += ms;
    ForgetIdleLocked();
    done_cv_.notify_all();
  }
}

std::shared_future<void> CpuPool::Async(std::function<void()> task) {
  auto packaged = std::make_shared<std::packaged_task<void()>>(std::move(task));
  std::shared_future<void> done = packaged->get_future().share();
  if (workers_.empty()) {
    (*packaged)();
    return done;
  }
  // A one-index job no caller drains: a worker runs it. The job owns the
  // function it points to.
  auto job = std::make_shared<Job>();
  job->n = 1;
  job->owned = [packaged](size_t) { (*packaged)(); };
  job->fn = &job->owned;
  job->tenant = CurrentCpuTenant();  // Drain runs the task under it
  {
    std::lock_guard lock(mutex_);
    ShareLocked(job->tenant);  // level with the least-served tenant now
    jobs_.push_back(std::move(job));
  }
  work_cv_.notify_one();
  return done;
}

void CpuPool::ParallelFor(size_t n, size_t chunk, const std::function<void(size_t)>& fn) {
  if (n == 0) return;
  auto job = std::make_shared<Job>();
  job->n = n;
  job->chunk = std::max<size_t>(chunk, 1);
  job->fn = &fn;
  job->stop = CurrentStopToken();
  job->tenant = CurrentCpuTenant();
  const bool parallel = !workers_.empty() && n > job->chunk;
  if (parallel) {
    {
      std::lock_guard lock(mutex_);
      ShareLocked(job->tenant);  // level with the least-served tenant now
      jobs_.push_back(job);
    }
    work_cv_.notify_all();
  }
  // The caller runs its own loop to the end, whatever else is queued.
  const double ms = Drain(*job, 0.0);
  if (!parallel) return;
  std::unique_lock lock(mutex_);
  // Every index is taken; wait for the workers still running theirs.
  done_cv_.wait(lock, [&] { return job->active == 0; });
  jobs_.erase(std::remove(jobs_.begin(), jobs_.end(), job), jobs_.end());
  if (auto it = shares_.find(job->tenant); it != shares_.end()) it->second.cpu_ms += ms;
  ForgetIdleLocked();
}

}  // namespace gistream
