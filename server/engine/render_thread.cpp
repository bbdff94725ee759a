#include "engine/render_thread.h"

#include "gl/debug_output.h"

namespace gistream {

absl::StatusOr<std::unique_ptr<RenderThread>> RenderThread::Start(int egl_device, Tick tick) {
  auto self = std::unique_ptr<RenderThread>(new RenderThread());
  self->tick_ = std::move(tick);
  self->egl_device_ = egl_device;
  std::promise<absl::Status> started;
  std::future<absl::Status> started_future = started.get_future();
  RenderThread* raw = self.get();
  self->thread_ = std::thread([raw, egl_device, &started] {
    auto context = gl::EglContext::Create(egl_device);
    if (!context.ok()) {
      started.set_value(context.status());
      return;
    }
    raw->context_ = std::move(context).value();
    if (absl::Status st = raw->context_->MakeCurrent(); !st.ok()) {
      raw->context_.reset();
      started.set_value(st);
      return;
    }
    gl::InstallDebugOutput();
    started.set_value(absl::OkStatus());
    raw->Loop();
    if (raw->context_) raw->context_->ReleaseCurrent();
    raw->context_.reset();
  });
  absl::Status status = started_future.get();
  if (!status.ok()) {
    self->thread_.join();
    return status;
  }
  return self;
}

RenderThread::~RenderThread() { Stop(); }

absl::Status RenderThread::RecreateContext() {
  if (context_) context_->ReleaseCurrent();
  context_.reset();
  GS_ASSIGN_OR_RETURN(std::unique_ptr<gl::EglContext> context, gl::EglContext::Create(egl_device_));
  GS_RETURN_IF_ERROR(context->MakeCurrent());
  context_ = std::move(context);
  gl::InstallDebugOutput();
  return absl::OkStatus();
}

bool RenderThread::Post(std::function<void()> job) {
  {
    std::lock_guard lock(mutex_);
    // Jobs queued before Stop() run (they are ahead of its last job); later
    // ones would wait forever on a thread that has ended.
    if (stopping_ || !thread_.joinable()) return false;
    jobs_.push_back(std::move(job));
  }
  cv_.notify_one();
  return true;
}

void RenderThread::Wake() {
  {
    std::lock_guard lock(mutex_);
    wake_ = true;
  }
  cv_.notify_one();
}

void RenderThread::Stop(std::function<void()> last) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ || !thread_.joinable()) return;
    if (last) jobs_.push_back(std::move(last));
    stopping_ = true;
  }
  cv_.notify_one();
  thread_.join();
}

void RenderThread::Loop() {
  Clock::time_point next = Clock::time_point::min();
  for (;;) {
    std::deque<std::function<void()>> jobs;
    bool stop = false;
    {
      std::unique_lock lock(mutex_);
      if (jobs_.empty() && !wake_ && !stopping_) {
        if (next == Clock::time_point::max()) {
          cv_.wait(lock, [&] { return !jobs_.empty() || wake_ || stopping_; });
        } else if (next > Clock::now()) {
          cv_.wait_until(lock, next, [&] { return !jobs_.empty() || wake_ || stopping_; });
        }
      }
      jobs.swap(jobs_);
      wake_ = false;
      stop = stopping_;
    }
    const Clock::time_point busy_from = Clock::now();
    for (auto& job : jobs) job();
    if (stop) return;
    next = tick_();
    busy_.AddBusy(busy_from, Clock::now());
  }
}

}  // namespace gistream
