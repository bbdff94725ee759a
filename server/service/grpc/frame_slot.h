// The one unsent frame a Session stream holds. A slow reader's frames are
// replaced, never queued; the replaced ones are counted. Video frames
// (H.264/HEVC/AV1 with an image) are predicted from the ones before, so
// after a replaced one the slot refuses delta frames until a key frame and
// asks for one (once per loss). Not thread-safe: the reactor's mutex
// guards it.
#pragma once

#include <cstdint>
#include <memory>

#include "service/engine.h"

namespace gistream::service {

class FrameSlot {
 public:
  struct Offered {
    uint32_t dropped = 0;            // frames dropped by this offer
    bool request_key_frame = false;  // ask the engine for a key frame
  };
  Offered Offer(std::shared_ptr<const EncodedFrame> frame);
  // The frame to send next (null when none); the slot is empty after.
  std::shared_ptr<const EncodedFrame> Take() { return std::move(pending_); }
  bool empty() const { return pending_ == nullptr; }
  void Clear() { pending_.reset(); }

 private:
  std::shared_ptr<const EncodedFrame> pending_;
  bool awaiting_key_frame_ = false;
};

}  // namespace gistream::service
