#include "service/frame_slot.h"

namespace gistream::service {
namespace {

// A frame whose loss breaks the chain of frames predicted from it.
bool BreaksChain(const EncodedFrame& f) {
  return !f.image.empty() && (f.format == ImageFormat::kH264 || f.format == ImageFormat::kHevc ||
                              f.format == ImageFormat::kAv1);
}

bool IsDelta(const EncodedFrame& f) { return BreaksChain(f) && !f.key_frame; }

}  // namespace

void FrameSlot::DropOldest(Offered& out) {
  const std::shared_ptr<const EncodedFrame> lost = std::move(pending_.front());
  pending_.pop_front();
  ++out.dropped;
  if (!BreaksChain(*lost)) return;
  // The deltas queued after it were predicted from it.
  while (!pending_.empty() && IsDelta(*pending_.front())) {
    pending_.pop_front();
    ++out.dropped;
  }
  const bool key_frame_queued = !pending_.empty() && BreaksChain(*pending_.front());
  if (key_frame_queued) return;  // the chain restarts there
  // Ask once per loss; again when the lost frame was the key frame asked for.
  if (!awaiting_key_frame_ || lost->key_frame) out.request_key_frame = true;
  awaiting_key_frame_ = true;
}

FrameSlot::Offered FrameSlot::Offer(std::shared_ptr<const EncodedFrame> frame) {
  Offered out;
  while (pending_.size() >= capacity_) DropOldest(out);
  if (awaiting_key_frame_ && IsDelta(*frame)) {
    ++out.dropped;  // the client could not decode it
    return out;
  }
  if (BreaksChain(*frame) && frame->key_frame) awaiting_key_frame_ = false;
  pending_.push_back(std::move(frame));
  return out;
}

std::shared_ptr<const EncodedFrame> FrameSlot::Take() {
  if (pending_.empty()) return nullptr;
  std::shared_ptr<const EncodedFrame> next = std::move(pending_.front());
  pending_.pop_front();
  return next;
}

}  // namespace gistream::service
