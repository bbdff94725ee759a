#include "support/frame_queue.h"

#include <chrono>

#include <gtest/gtest.h>

namespace gistream::testing {
namespace {
constexpr auto kHangBound = std::chrono::minutes(2);
}  // namespace

void FrameQueue::OnFrame(std::shared_ptr<const EncodedFrame> frame) {
  std::lock_guard lock(mutex_);
  frames_.push_back(std::move(frame));
  cv_.notify_all();
}

void FrameQueue::OnUpdateRejected(uint64_t seq, const absl::Status& status) {
  std::lock_guard lock(mutex_);
  rejected_.emplace_back(seq, status);
  cv_.notify_all();
}

void FrameQueue::OnSessionFailed(const absl::Status& status) {
  std::lock_guard lock(mutex_);
  failed_ = status;
  cv_.notify_all();
}

std::shared_ptr<const EncodedFrame> FrameQueue::Next() {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, kHangBound, [&] { return next_ < frames_.size() || !failed_.ok(); });
  EXPECT_TRUE(failed_.ok()) << failed_;
  if (next_ >= frames_.size()) return nullptr;
  return frames_[next_++];
}

std::shared_ptr<const EncodedFrame> FrameQueue::WaitFor(
    const std::function<bool(const EncodedFrame&)>& want) {
  std::unique_lock lock(mutex_);
  std::shared_ptr<const EncodedFrame> found;
  cv_.wait_for(lock, kHangBound, [&] {
    for (const auto& f : frames_) {
      if (want(*f)) {
        found = f;
        break;
      }
    }
    return found != nullptr || !failed_.ok();
  });
  EXPECT_TRUE(failed_.ok()) << failed_;
  return found;
}

size_t FrameQueue::Count(const std::function<bool(const EncodedFrame&)>& which) const {
  std::lock_guard lock(mutex_);
  size_t n = 0;
  for (const auto& f : frames_) n += which(*f) ? 1 : 0;
  return n;
}

std::vector<std::pair<uint64_t, absl::Status>> FrameQueue::rejected() const {
  std::lock_guard lock(mutex_);
  return rejected_;
}

}  // namespace gistream::testing
