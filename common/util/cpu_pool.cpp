#include "util/cpu_pool.h"

#include "util/cancellation.h"

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <string>

namespace gistream {
namespace {

std::mutex g_config_mutex;
unsigned g_configured = 0;

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

void CpuPool::Drain(Job& job) {
  CancellationScope scope(job.stop);
  for (;;) {
    if (job.stop.stop_requested()) {
      job.next.store(job.n);  // the rest is not started
      return;
    }
    const size_t begin = job.next.fetch_add(job.chunk);
    if (begin >= job.n) return;
    const size_t end = std::min(job.n, begin + job.chunk);
    for (size_t i = begin; i < end; ++i) (*job.fn)(i);
  }
}

void CpuPool::WorkerLoop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    work_cv_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
    if (stop_) return;
    std::shared_ptr<Job> job = jobs_.front();
    if (job->next.load() >= job->n) {
      jobs_.pop_front();  // exhausted: its caller finishes it
      continue;
    }
    ++job->active;
    lock.unlock();
    Drain(*job);
    lock.lock();
    --job->active;
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
  {
    std::lock_guard lock(mutex_);
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
  const bool parallel = !workers_.empty() && n > job->chunk;
  if (parallel) {
    {
      std::lock_guard lock(mutex_);
      jobs_.push_back(job);
    }
    work_cv_.notify_all();
  }
  Drain(*job);
  if (!parallel) return;
  std::unique_lock lock(mutex_);
  // Every index is taken; wait for the workers still running theirs.
  done_cv_.wait(lock, [&] { return job->active == 0; });
  jobs_.erase(std::remove(jobs_.begin(), jobs_.end(), job), jobs_.end());
}

}  // namespace gistream
