// A FrameSink for tests that drive an engine session directly: it keeps
// every frame in arrival order, and waits (at most two minutes, a hang
// bound, never a timing threshold) for the next one or for one that
// matches. A failed session ends the waits with nullptr and fails the test.
#pragma once

#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "engine/engine.h"

namespace gistream::testing {

class FrameQueue final : public FrameSink {
 public:
  void OnFrame(std::shared_ptr<const EncodedFrame> frame) override;
  void OnUpdateRejected(uint64_t seq, const absl::Status& status) override;
  void OnSessionFailed(const absl::Status& status) override;

  // The next frame not yet taken by Next().
  std::shared_ptr<const EncodedFrame> Next();
  // The first frame received that matches `want` (taken or not), waiting
  // for one if there is none yet. (The first: later ones may be keep-alive
  // frames without an image.)
  std::shared_ptr<const EncodedFrame> WaitFor(const std::function<bool(const EncodedFrame&)>& want);
  // Frames received so far that match `which`.
  size_t Count(const std::function<bool(const EncodedFrame&)>& which) const;
  std::vector<std::pair<uint64_t, absl::Status>> rejected() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<std::shared_ptr<const EncodedFrame>> frames_;
  size_t next_ = 0;
  std::vector<std::pair<uint64_t, absl::Status>> rejected_;
  absl::Status failed_;
};

}  // namespace gistream::testing
