// FrameSlot, the session stream's one unsent frame: image frames are
// replaced and counted; a replaced video frame makes the slot refuse delta
// frames until a key frame, which it asks for once per loss (and again if
// that key frame is lost too); unchanged frames never break the chain.
#include <gtest/gtest.h>

#include "service/grpc/frame_slot.h"

namespace gistream::service {
namespace {

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

}  // namespace
}  // namespace gistream::service
