// The unsent frames a Session stream holds, oldest first, at most
// `capacity`: one for a continuous session (a slow reader's frames are
// replaced, never queued), the on-request window for an on-request session
// (which never asks the engine for more, so nothing is replaced). A frame
// pushed out over capacity is dropped and counted. Video frames
// (H.264/HEVC/AV1 with an image) are predicted from the ones before, so
// after a dropped one the slot drops the deltas queued after it, refuses
// new deltas until a key frame, and asks for one (once per loss). Not
// thread-safe: the reactor's mutex guards it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>

#include "engine/engine.h"

namespace gistream::service {

class FrameSlot {
 public:
  explicit FrameSlot(size_t capacity = 1) : capacity_(capacity < 1 ? 1 : capacity) {}
  void set_capacity(size_t capacity) { capacity_ = capacity < 1 ? 1 : capacity; }

  struct Offered {
    uint32_t dropped = 0;            // frames dropped by this offer
    bool request_key_frame = false;  // ask the engine for a key frame
  };
  Offered Offer(std::shared_ptr<const EncodedFrame> frame);
  // The oldest frame to send (null when none), taken out of the slot.
  std::shared_ptr<const EncodedFrame> Take();
  bool empty() const { return pending_.empty(); }
  size_t size() const { return pending_.size(); }
  void Clear() { pending_.clear(); }

 private:
  void DropOldest(Offered& out);

  std::deque<std::shared_ptr<const EncodedFrame>> pending_;
  size_t capacity_;
  bool awaiting_key_frame_ = false;
};

}  // namespace gistream::service
