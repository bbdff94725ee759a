#include "service/grpc/frame_slot.h"

namespace gistream::service {
namespace {

// A frame whose loss breaks the chain of frames predicted from it.
bool BreaksChain(const EncodedFrame& f) {
  return !f.image.empty() && (f.format == ImageFormat::kH264 || f.format == ImageFormat::kHevc ||
                              f.format == ImageFormat::kAv1);
}

}  // namespace

FrameSlot::Offered FrameSlot::Offer(std::shared_ptr<const EncodedFrame> frame) {
  Offered out;
  if (pending_ != nullptr) {
    ++out.dropped;
    if (BreaksChain(*pending_)) {
      // Ask once per loss; again when the lost frame was the key frame
      // asked for.
      out.request_key_frame = !awaiting_key_frame_ || pending_->key_frame;
      awaiting_key_frame_ = true;
    }
    pending_.reset();
  }
  if (awaiting_key_frame_ && BreaksChain(*frame) && !frame->key_frame) {
    ++out.dropped;  // the client could not decode it
    return out;
  }
  if (BreaksChain(*frame) && frame->key_frame) awaiting_key_frame_ = false;
  pending_ = std::move(frame);
  return out;
}

}  // namespace gistream::service
