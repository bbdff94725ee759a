// The thread that owns the GL context. Other threads post jobs to it; it
// runs them in order, and between jobs calls the tick function (the frame
// scheduler), sleeping until the time the tick asks for or the next job.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>

#include "gl/egl_context.h"
#include "engine/busy_meter.h"
#include "util/status.h"

namespace gistream {

class RenderThread {
 public:
  using Clock = std::chrono::steady_clock;
  // Returns when the tick wants to run next (Clock::time_point::max(): only
  // when a job arrives).
  using Tick = std::function<Clock::time_point()>;

  // Creates the context on the new thread; fails if it cannot.
  static absl::StatusOr<std::unique_ptr<RenderThread>> Start(int egl_device, Tick tick);
  ~RenderThread();  // Stop()

  // Runs `job` on the render thread; false (and `job` dropped) once Stop()
  // has begun, when no job would run any more.
  bool Post(std::function<void()> job);
  // Runs `job` on the render thread and waits for its result; `if_stopped`
  // when the thread is stopping (a caller racing shutdown must not wait
  // for a job that never runs).
  template <typename T>
  T Call(std::function<T()> job, T if_stopped) {
    auto task = std::make_shared<std::packaged_task<T()>>(std::move(job));
    std::future<T> result = task->get_future();
    if (!Post([task] { (*task)(); })) return if_stopped;
    return result.get();
  }
  // Wakes the scheduler (a session became due).
  void Wake();
  // Runs `last` on the render thread (with the context still current),
  // then ends the thread. Idempotent.
  void Stop(std::function<void()> last = {});

  const gl::EglContext& context() const { return *context_; }
  // Its busy share (jobs and ticks, not waits) over the last 5 s.
  double busy_ratio() const { return busy_.Ratio(); }
  // On the render thread, after a GPU reset: drops the context (every GL
  // object in it must be gone already) and makes a new one current on the
  // same device. On failure the thread has no context.
  absl::Status RecreateContext();
  bool on_render_thread() const { return std::this_thread::get_id() == thread_.get_id(); }

 private:
  RenderThread() = default;
  void Loop();

  Tick tick_;
  int egl_device_ = -1;
  std::unique_ptr<gl::EglContext> context_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> jobs_;
  bool wake_ = false;
  bool stopping_ = false;
  BusyMeter busy_;
  std::thread thread_;
};

}  // namespace gistream
