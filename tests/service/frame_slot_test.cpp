// FrameSlot, the session stream's unsent frames: over capacity (one for a
// continuous session) image frames are replaced and counted; a replaced
// video frame makes the slot refuse delta frames until a key frame, which it
// asks for once per loss (and again if that key frame is lost too);
// unchanged frames never break the chain.
#include <gtest/gtest.h>

#include "service/frame_slot.h"

namespace gistream::service {
namespace frame_slot_test {

std::shared_ptr<const EncodedFrame> Frame(ImageFormat format, bool key, bool image = true,
                                          uint64_t number = 0) {
  auto f = std::make_shared<EncodedFrame>();
  f->format = format;
  f->key_frame = key;
  f->unchanged = !image;
  f->image = image ? "bytes" : "";
  f->frame_number = number;
  return f;
}

TEST(FrameSlot, ImageFramesAreReplaced) {
  FrameSlot slot;
  EXPECT_EQ(slot.Offer(Frame(ImageFormat::kJpeg, true, true, 1)).dropped, 0u);
  const auto offered = slot.Offer(Frame(ImageFormat::kJpeg, true, true, 2));
  EXPECT_EQ(offered.dropped, 1u);
  EXPECT_FALSE(offered.request_key_frame);
  EXPECT_EQ(slot.Take()->frame_number, 2u);
  EXPECT_TRUE(slot.empty());
}

TEST(FrameSlot, ALostVideoFrameHoldsDeltasUntilAKeyFrame) {
  FrameSlot slot;
  slot.Offer(Frame(ImageFormat::kH264, true, true, 1));
  ASSERT_EQ(slot.Take()->frame_number, 1u);  // sent
  slot.Offer(Frame(ImageFormat::kH264, false, true, 2));
  // Frame 2 is replaced unsent: 3 cannot be decoded without it.
  auto offered = slot.Offer(Frame(ImageFormat::kH264, false, true, 3));
  EXPECT_EQ(offered.dropped, 2u);
  EXPECT_TRUE(offered.request_key_frame);
  EXPECT_TRUE(slot.empty());
  // More deltas: dropped, no second request; an unchanged frame passes.
  offered = slot.Offer(Frame(ImageFormat::kH264, false, true, 4));
  EXPECT_EQ(offered.dropped, 1u);
  EXPECT_FALSE(offered.request_key_frame);
  EXPECT_EQ(slot.Offer(Frame(ImageFormat::kH264, false, false, 5)).dropped, 0u);
  EXPECT_EQ(slot.Take()->frame_number, 5u);
  // The key frame is kept, and deltas flow again after it.
  EXPECT_EQ(slot.Offer(Frame(ImageFormat::kH264, true, true, 6)).dropped, 0u);
  EXPECT_EQ(slot.Take()->frame_number, 6u);
  EXPECT_EQ(slot.Offer(Frame(ImageFormat::kH264, false, true, 7)).dropped, 0u);
  EXPECT_EQ(slot.Take()->frame_number, 7u);
}

TEST(FrameSlot, ALostKeyFrameIsAskedForAgain) {
  FrameSlot slot;
  slot.Offer(Frame(ImageFormat::kHevc, false, true, 1));
  EXPECT_TRUE(slot.Offer(Frame(ImageFormat::kHevc, false, true, 2)).request_key_frame);
  slot.Offer(Frame(ImageFormat::kHevc, true, true, 3));  // the key frame, not yet sent
  const auto offered = slot.Offer(Frame(ImageFormat::kHevc, false, true, 4));
  EXPECT_TRUE(offered.request_key_frame);
  EXPECT_EQ(offered.dropped, 2u);  // the key frame, and 4 that needs it
  EXPECT_TRUE(slot.empty());
}

TEST(FrameSlot, AWindowKeepsFramesInOrderUpToItsCapacity) {
  FrameSlot slot(2);
  EXPECT_EQ(slot.Offer(Frame(ImageFormat::kJpeg, true, true, 1)).dropped, 0u);
  EXPECT_EQ(slot.Offer(Frame(ImageFormat::kJpeg, true, true, 2)).dropped, 0u);
  EXPECT_EQ(slot.size(), 2u);
  // Over capacity the oldest goes.
  EXPECT_EQ(slot.Offer(Frame(ImageFormat::kJpeg, true, true, 3)).dropped, 1u);
  EXPECT_EQ(slot.Take()->frame_number, 2u);
  EXPECT_EQ(slot.Take()->frame_number, 3u);
  EXPECT_EQ(slot.Take(), nullptr);
}

TEST(FrameSlot, AVideoFrameDroppedFromAWindowTakesItsQueuedDeltas) {
  FrameSlot slot(3);
  slot.Offer(Frame(ImageFormat::kAv1, true, true, 1));
  slot.Offer(Frame(ImageFormat::kAv1, false, true, 2));
  slot.Offer(Frame(ImageFormat::kAv1, false, true, 3));
  // 1 is pushed out: 2 and 3 were predicted from it.
  auto offered = slot.Offer(Frame(ImageFormat::kAv1, false, true, 4));
  EXPECT_EQ(offered.dropped, 4u);
  EXPECT_TRUE(offered.request_key_frame);
  EXPECT_TRUE(slot.empty());
  // A key frame already queued after the lost one restarts the chain: no request.
  FrameSlot keyed(2);
  keyed.Offer(Frame(ImageFormat::kH264, false, true, 1));
  keyed.Offer(Frame(ImageFormat::kH264, true, true, 2));
  offered = keyed.Offer(Frame(ImageFormat::kH264, false, true, 3));
  EXPECT_EQ(offered.dropped, 1u);
  EXPECT_FALSE(offered.request_key_frame);
  EXPECT_EQ(keyed.Take()->frame_number, 2u);
  EXPECT_EQ(keyed.Take()->frame_number, 3u);
}

}  // namespace frame_slot_test
}  // namespace gistream::service
