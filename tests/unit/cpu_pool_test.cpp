// The one CPU pool: it runs on at most the threads it was given, visits
// every index once (also for concurrent and nested loops), and reads the
// cgroup CPU quota of both cgroup versions. Cancellation
// (util/cancellation.h): a loop under a cancelled token starts no more
// indices, its workers see the caller's token, and a cancelled background
// job ends and is never taken.
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/background_job.h"
#include "util/cancellation.h"
#include "util/cpu_pool.h"
#include "util/memory_budget.h"
#include "util/parallel_for.h"

namespace gistream {
namespace cpu_pool_test {

namespace fs = std::filesystem;

std::set<std::thread::id> ThreadsUsed(CpuPool& pool, size_t n, std::vector<int>& visits) {
  std::mutex mutex;
  std::set<std::thread::id> ids;
  visits.assign(n, 0);
  pool.ParallelFor(n, 1, [&](size_t i) {
    // Enough work per index that every worker gets a share.
    volatile double x = 0.0;
    for (int k = 0; k < 2000; ++k) x = x + double(k) * 1e-9;
    std::lock_guard lock(mutex);
    ids.insert(std::this_thread::get_id());
    ++visits[i];
  });
  return ids;
}

TEST(CpuPool, RunsOnAtMostItsThreadsAndVisitsEveryIndexOnce) {
  for (unsigned threads : {1u, 2u, 3u}) {
    CpuPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    std::vector<int> visits;
    const std::set<std::thread::id> ids = ThreadsUsed(pool, 5000, visits);
    EXPECT_LE(ids.size(), threads);
    EXPECT_GE(ids.size(), 1u);
    for (size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i], 1) << "index " << i;
    if (threads == 1) {
      EXPECT_EQ(*ids.begin(), std::this_thread::get_id());
    }
  }
}

TEST(CpuPool, ConcurrentAndNestedLoopsEachFinishWhole) {
  CpuPool pool(3);
  std::atomic<size_t> sum_a{0}, sum_b{0};
  std::thread other([&] { pool.ParallelFor(1000, 7, [&](size_t i) { sum_b += i; }); });
  pool.ParallelFor(100, 1, [&](size_t i) {
    // A nested loop drains on the calling worker if no one else helps.
    pool.ParallelFor(10, 1, [&](size_t j) { sum_a += i * 10 + j; });
  });
  other.join();
  EXPECT_EQ(sum_a.load(), 999u * 1000u / 2u);
  EXPECT_EQ(sum_b.load(), 999u * 1000u / 2u);
}

TEST(CpuPool, AsyncTasksRunOffTheCallerAndMayUseLoops) {
  for (unsigned threads : {1u, 3u}) {
    CpuPool pool(threads);
    std::atomic<size_t> sum{0};
    std::thread::id ran_on;
    std::shared_future<void> done = pool.Async([&] {
      ran_on = std::this_thread::get_id();
      pool.ParallelFor(100, 3, [&](size_t i) { sum += i; });
    });
    done.wait();
    EXPECT_EQ(sum.load(), 99u * 100u / 2u);
    // With workers the task runs on one of them; without, on the caller.
    if (threads == 1) {
      EXPECT_EQ(ran_on, std::this_thread::get_id());
    } else {
      EXPECT_NE(ran_on, std::this_thread::get_id());
    }
  }
}

TEST(CpuPool, EmptyAndTinyLoops) {
  CpuPool pool(2);
  int calls = 0;
  pool.ParallelFor(0, 1, [&](size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
  pool.ParallelFor(1, 8, [&](size_t) { ++calls; });  // one chunk: the caller alone
  EXPECT_EQ(calls, 1);
}

TEST(CpuPool, ACancelledLoopStartsNoMoreIndicesAndItsWorkersSeeTheToken) {
  CpuPool pool(3);
  std::stop_source stop;
  CancellationScope scope(stop.get_token());
  std::atomic<size_t> calls{0}, after_cancel{0}, without_token{0};
  pool.ParallelFor(100'000, 1, [&](size_t i) {
    if (stop.stop_requested()) after_cancel += 1;
    calls += 1;
    if (!CurrentStopToken().stop_possible()) without_token += 1;
    if (i == 10) stop.request_stop();
  });
  // Counted from the cancel, not from index 10: another thread may run
  // many indices while the one holding index 10 waits for a core (it did,
  // under ThreadSanitizer on 2 cores). After the cancel each of the 3
  // threads may start at most the one index whose check it had passed.
  EXPECT_GE(calls.load(), 11u);
  EXPECT_LT(calls.load(), 100'000u);
  EXPECT_LE(after_cancel.load(), 3u);
  EXPECT_EQ(without_token.load(), 0u) << "a worker ran an index without the caller's token";
  EXPECT_TRUE(Cancelled());
}

TEST(CpuPool, OutsideAScopeNothingIsCancelled) {
  EXPECT_FALSE(Cancelled());
  std::stop_source stop;
  stop.request_stop();
  {
    CancellationScope scope(stop.get_token());
    EXPECT_TRUE(Cancelled());
    {
      std::stop_source inner;
      CancellationScope nested(inner.get_token());
      EXPECT_FALSE(Cancelled());  // the innermost decides
    }
    EXPECT_TRUE(Cancelled());
  }
  EXPECT_FALSE(Cancelled());
}

struct SpinJob {
  std::atomic<bool> started{false};
  uint64_t spins = 0;
  bool saw_cancel = false;  // why the spin ended (else the hour ran out)
  std::atomic<bool> ended{false};
};

// (A pool of one thread runs a job on the caller: these need a worker.)
TEST(BackgroundJob, ACancelledJobEndsAndIsNeverTaken) {
  if (CpuPool::Get().threads() < 2) GTEST_SKIP() << "the CPU pool has no worker here";
  BackgroundJob<SpinJob> job;
  auto data = std::make_shared<SpinJob>();
  // Spins until cancelled (an hour's bound: the hang is the failure).
  job.Start(data, [](SpinJob& j) {
    j.started = true;
    const auto end = std::chrono::steady_clock::now() + std::chrono::hours(1);
    while (!Cancelled() && std::chrono::steady_clock::now() < end) j.spins += 1;
  });
  while (!data->started) std::this_thread::yield();
  EXPECT_EQ(job.TakeIfDone(), nullptr);  // still running
  job.Cancel();
  while (job.executing()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_EQ(job.TakeIfDone(), nullptr) << "a cancelled job's partial result was taken";
  EXPECT_FALSE(job.running());
}

TEST(BackgroundJob, TheDestructorCancelsTheJob) {
  if (CpuPool::Get().threads() < 2) GTEST_SKIP() << "the CPU pool has no worker here";
  auto data = std::make_shared<SpinJob>();
  {
    BackgroundJob<SpinJob> job;
    job.Start(data, [](SpinJob& j) {
      j.started = true;
      const auto end = std::chrono::steady_clock::now() + std::chrono::hours(1);
      while (!Cancelled() && std::chrono::steady_clock::now() < end) j.spins += 1;
      j.saw_cancel = Cancelled();
      j.ended = true;
    });
    while (!data->started) std::this_thread::yield();
  }  // returns once the job saw the cancel
  // (Not spins > 0: the cancel may come before the first spin.)
  EXPECT_TRUE(data->ended) << "the destructor returned while the job ran";
  EXPECT_TRUE(data->saw_cancel);
}

class CgroupDir : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ =
        fs::temp_directory_path() /
        ("gistream_cgroup_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "cpu");
  }
  void TearDown() override { fs::remove_all(root_); }
  void Write(const fs::path& rel, const std::string& text) { std::ofstream(root_ / rel) << text; }
  fs::path root_;
};

TEST_F(CgroupDir, V2QuotaRoundsUpAndMaxMeansNoLimit) {
  Write("cpu.max", "200000 100000\n");
  EXPECT_EQ(CgroupCpuLimit(root_.string()), 2u);
  Write("cpu.max", "150000 100000\n");  // 1.5 CPUs: two threads share them
  EXPECT_EQ(CgroupCpuLimit(root_.string()), 2u);
  Write("cpu.max", "50000 100000\n");  // half a CPU: still one thread
  EXPECT_EQ(CgroupCpuLimit(root_.string()), 1u);
  Write("cpu.max", "max 100000\n");
  EXPECT_EQ(CgroupCpuLimit(root_.string()), 0u);
}

TEST_F(CgroupDir, V1QuotaAndNoFilesAtAll) {
  EXPECT_EQ(CgroupCpuLimit(root_.string()), 0u);
  Write("cpu/cpu.cfs_quota_us", "400000\n");
  Write("cpu/cpu.cfs_period_us", "100000\n");
  EXPECT_EQ(CgroupCpuLimit(root_.string()), 4u);
  Write("cpu/cpu.cfs_quota_us", "-1\n");
  EXPECT_EQ(CgroupCpuLimit(root_.string()), 0u);
}

TEST_F(CgroupDir, MemoryLimitFromV2ThenV1AndTheBudgetTakesTheLower) {
  EXPECT_EQ(CgroupMemoryLimit(root_.string()), 0u);  // no files: no limit
  fs::create_directories(root_ / "memory");
  Write("memory/memory.limit_in_bytes", "9223372036854771712\n");  // v1 "unlimited"
  EXPECT_EQ(CgroupMemoryLimit(root_.string()), 9223372036854771712ull);
  Write("memory/memory.limit_in_bytes", "4294967296\n");
  EXPECT_EQ(CgroupMemoryLimit(root_.string()), 4294967296ull);
  Write("memory.max", "max\n");  // v2 first: no limit
  EXPECT_EQ(CgroupMemoryLimit(root_.string()), 0u);
  Write("memory.max", "8589934592\n");  // a pod's 8 GiB
  EXPECT_EQ(CgroupMemoryLimit(root_.string()), 8589934592ull);
  const uint64_t gib = uint64_t(1) << 30;
  // A 64 GiB node, an 8 GiB pod: 6 GiB, not 48 (issue 31).
  EXPECT_EQ(MemoryLimitFor(64 * gib, 8 * gib), 6 * gib);
  EXPECT_EQ(MemoryLimitFor(64 * gib, 0), 48 * gib);
  EXPECT_EQ(MemoryLimitFor(8 * gib, 9223372036854771712ull), 6 * gib);
}

// Fair share between tenants (issue 30, item 3): one worker, tenant A's
// three background tasks queued before tenant B's one. In arrival order B
// ran last; now B, whose pool time is the least, runs as soon as the
// worker is free (after A's first task).
TEST(CpuPool, AnotherTenantsTaskIsNotQueuedBehindATenantsBacklog) {
  CpuPool pool(2);  // one worker
  std::mutex mutex;
  std::vector<std::string> order;
  auto task = [&](std::string name, int ms) {
    return [&, name, ms] {
      {
        std::lock_guard lock(mutex);
        order.push_back(name + ":" + CurrentCpuTenant());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(ms));
    };
  };
  std::vector<std::shared_future<void>> done;
  {
    const CpuTenantScope a("a");
    for (const char* name : {"a1", "a2", "a3"}) done.push_back(pool.Async(task(name, 60)));
  }
  {
    const CpuTenantScope b("b");
    done.push_back(pool.Async(task("b1", 1)));
  }
  for (auto& d : done) d.wait();
  EXPECT_EQ(order, (std::vector<std::string>{"a1:a", "b1:b", "a2:a", "a3:a"}));
  // The worker leaves its share just after the last future is ready.
  for (int i = 0; i < 2000 && !pool.Shares().empty(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(pool.Shares().empty()) << "nothing queued or running: no share kept";
}

// A worker chooses again after each slice (kCpuSliceMs): while tenant A's
// long loop runs, tenant B's loop gets workers, not its caller alone
// (without slices the workers stayed on A's loop until it was exhausted).
TEST(CpuPool, ATenantsLongLoopLeavesWorkersToAnother) {
  CpuPool pool(3);  // two workers and each caller
  std::atomic<bool> b_done{false};
  std::thread a([&] {
    const CpuTenantScope tenant("a");
    pool.ParallelFor(100000, 1, [&](size_t) {
      if (b_done.load()) return;  // the rest of A's loop is quick
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    });
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(30));  // A holds both workers
  std::atomic<int> on_workers{0};
  std::thread b([&] {
    const CpuTenantScope tenant("b");
    const std::thread::id caller = std::this_thread::get_id();
    pool.ParallelFor(60, 1, [&](size_t) {
      EXPECT_EQ(CurrentCpuTenant(), "b");
      if (std::this_thread::get_id() != caller) on_workers.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    });
    b_done.store(true);
  });
  b.join();
  a.join();
  EXPECT_GT(on_workers.load(), 0);
}

TEST(CpuPool, DefaultSizeIsWithinTheMachine) {
  const unsigned threads = DefaultCpuThreads();
  EXPECT_GE(threads, 1u);
  EXPECT_LE(threads, std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace cpu_pool_test
}  // namespace gistream
