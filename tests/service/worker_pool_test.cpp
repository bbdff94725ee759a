#include "service/worker_pool.h"

#include <atomic>
#include <latch>

#include <gtest/gtest.h>

namespace gistream::service {
namespace worker_pool_test {

TEST(WorkerPool, RunsEveryAcceptedJob) {
  std::atomic<int> ran{0};
  {
    WorkerPool pool({.threads = 3, .max_queued = 100});
    for (int i = 0; i < 50; ++i) ASSERT_TRUE(pool.Submit([&] { ++ran; }).ok());
  }  // destructor drains
  EXPECT_EQ(ran.load(), 50);
}

TEST(WorkerPool, FullQueueIsResourceExhausted) {
  // The latches outlive the pool: its destructor joins the worker, which
  // may still be inside release.wait() (ASan: stack-use-after-scope).
  std::latch started(1);
  std::latch release(1);
  WorkerPool pool({.threads = 1, .max_queued = 2});
  ASSERT_TRUE(pool.Submit([&] {
                    started.count_down();
                    release.wait();
                  })
                  .ok());
  started.wait();  // the only thread is busy now
  EXPECT_TRUE(pool.Submit([] {}).ok());
  EXPECT_TRUE(pool.Submit([] {}).ok());
  const absl::Status full = pool.Submit([] {});
  EXPECT_EQ(full.code(), absl::StatusCode::kResourceExhausted) << full;
  release.count_down();
}

TEST(WorkerPool, StopRunsQueuedJobsThenRefuses) {
  WorkerPool pool({.threads = 1, .max_queued = 10});
  std::atomic<int> ran{0};
  std::latch release(1);
  ASSERT_TRUE(pool.Submit([&] { release.wait(); }).ok());
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(pool.Submit([&] { ++ran; }).ok());
  std::thread stopper([&] { pool.Stop(); });
  release.count_down();
  stopper.join();
  EXPECT_EQ(ran.load(), 5);
  EXPECT_EQ(pool.Submit([] {}).code(), absl::StatusCode::kUnavailable);
  pool.Stop();  // idempotent
}

}  // namespace worker_pool_test
}  // namespace gistream::service
