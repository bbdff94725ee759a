// Video encoding (common/encode/video, service/frame_encoder) without GL:
// libx264 access units decode with libavcodec to a picture close to the
// input; key frames come first, at the set interval and on request; odd
// sizes are padded; unchanged pixels are recognised; a missing encoder is
// FAILED_PRECONDITION naming encoding.format.
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "encode/encode.h"
#include "encode/video/video_decoder.h"
#include "encode/video/video_encoder.h"
#include "engine/frame_encoder.h"

namespace gistream {
namespace video_encoder_test {

// A rendered-looking test picture: smooth shading, a hard red/green edge
// (the Cornell box's walls: the worst case for 4:2:0 chroma) and a few
// thin lines.
std::vector<uint8_t> TestPicture(int w, int h, int shift = 0) {
  std::vector<uint8_t> rgba(size_t(w) * size_t(h) * 4);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t* p = rgba.data() + (size_t(y) * size_t(w) + size_t(x)) * 4;
      const int xs = x + shift;
      const float shade = 0.3f + 0.6f * float(y) / float(h);
      if (xs < w / 4) {
        p[0] = uint8_t(200 * shade), p[1] = uint8_t(30 * shade), p[2] = uint8_t(30 * shade);
      } else if (xs > 3 * w / 4) {
        p[0] = uint8_t(30 * shade), p[1] = uint8_t(180 * shade), p[2] = uint8_t(40 * shade);
      } else {
        const uint8_t v = uint8_t(220 * shade);
        p[0] = p[1] = p[2] = v;
      }
      if ((xs % 32) == 7) p[0] = p[1] = p[2] = 20;
      p[3] = 255;
    }
  }
  return rgba;
}

// PSNR over R, G, B of two 8-bit RGBA images of the same size (the first
// `w` x `h` pixels of `b`, whose rows are `bw` wide).
double Psnr(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int w, int h, int bw) {
  double sum = 0.0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double d = double(a[(size_t(y) * size_t(w) + size_t(x)) * 4 + size_t(c)]) -
                         double(b[(size_t(y) * size_t(bw) + size_t(x)) * 4 + size_t(c)]);
        sum += d * d;
      }
    }
  }
  const double mse = sum / (3.0 * w * h);
  return mse == 0.0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

VideoEncoderOptions X264(int w, int h) {
  VideoEncoderOptions o;
  o.width = w;
  o.height = h;
  o.encoders = {"libx264"};  // the same encoder with and without a GPU
  return o;
}

TEST(VideoEncoder, H264DecodesCloseToTheInput) {
  const int w = 128, h = 96;
  auto encoder = VideoEncoder::Open(X264(w, h));
  ASSERT_TRUE(encoder.ok()) << encoder.status();
  auto decoder = VideoDecoder::Open(VideoCodec::kH264);
  ASSERT_TRUE(decoder.ok()) << decoder.status();
  for (int i = 0; i < 3; ++i) {
    const std::vector<uint8_t> picture = TestPicture(w, h, 3 * i);
    auto unit = (*encoder)->Encode(picture, false);
    ASSERT_TRUE(unit.ok()) << unit.status();
    // Annex-B: starts with a start code.
    ASSERT_GE(unit->bytes.size(), 4u);
    const std::string& b = unit->bytes;
    EXPECT_TRUE(b[0] == 0 && b[1] == 0 && (b[2] == 1 || (b[2] == 0 && b[3] == 1)));
    EXPECT_EQ(unit->key_frame, i == 0);
    auto decoded = (*decoder)->Decode(
        {reinterpret_cast<const uint8_t*>(unit->bytes.data()), unit->bytes.size()});
    ASSERT_TRUE(decoded.ok()) << decoded.status();
    ASSERT_EQ(decoded->width, w);
    ASSERT_EQ(decoded->height, h);
    // CRF 23 on this picture: 4:2:0 chroma across the red/green edges and
    // the 8-bit YUV round trip bound it; 30 dB is an RMS error of 8/255.
    const double psnr = Psnr(picture, decoded->rgba, w, h, w);
    EXPECT_GE(psnr, 30.0) << "frame " << i;
  }
}

TEST(VideoEncoder, KeyFramesFirstAtTheIntervalAndOnRequest) {
  VideoEncoderOptions o = X264(64, 64);
  o.key_frame_interval = 4;
  auto encoder = VideoEncoder::Open(o);
  ASSERT_TRUE(encoder.ok()) << encoder.status();
  std::vector<bool> keys;
  for (int i = 0; i < 10; ++i) {
    auto unit = (*encoder)->Encode(TestPicture(64, 64, i), /*key_frame=*/i == 6);
    ASSERT_TRUE(unit.ok()) << unit.status();
    keys.push_back(unit->key_frame);
  }
  // Frame 0 and every 4th after the last key frame; frame 6 on request
  // (which restarts the interval: 6, then 10 would be next).
  EXPECT_EQ(keys,
            (std::vector<bool>{true, false, false, false, true, false, true, false, false, false}));
}

TEST(VideoEncoder, OddSizesAndUnknownEncodersAreRefused) {
  auto odd = VideoEncoder::Open(X264(63, 64));
  EXPECT_EQ(odd.status().code(), absl::StatusCode::kInvalidArgument);
  VideoEncoderOptions o = X264(64, 64);
  o.encoders = {"no_such_encoder"};
  auto missing = VideoEncoder::Open(o);
  EXPECT_EQ(missing.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(missing.status().message().find("no_such_encoder"), std::string::npos);
}

TEST(FrameEncoder, UnknownEncoderIsFailedPreconditionNamingTheField) {
  EncodingOptions e;
  e.format = ImageFormat::kH264;
  e.video_encoders = {"no_such_encoder"};
  const absl::Status status = ValidateEncoding(e);
  EXPECT_EQ(status.code(), absl::StatusCode::kFailedPrecondition) << status;
  EXPECT_NE(status.message().find("encoding.format"), std::string::npos) << status;
  e.video_encoders = {"libx264"};
  EXPECT_TRUE(ValidateEncoding(e).ok());
  e.crf = 0;
  EXPECT_EQ(ValidateEncoding(e).code(), absl::StatusCode::kInvalidArgument);
  // Every codec is either available or refused by name.
  for (ImageFormat f : {ImageFormat::kHevc, ImageFormat::kAv1}) {
    EncodingOptions v;
    v.format = f;
    const absl::Status s = ValidateEncoding(v);
    EXPECT_TRUE(s.ok() || (s.code() == absl::StatusCode::kFailedPrecondition &&
                           s.message().find("encoding.format") != std::string::npos))
        << s;
  }
}

TEST(FrameEncoder, RecognisesUnchangedPixels) {
  FrameEncoder encoder;
  const std::vector<uint8_t> a = TestPicture(16, 16), b = TestPicture(16, 16, 1);
  EXPECT_FALSE(encoder.SameAsLast(a));
  EXPECT_TRUE(encoder.SameAsLast(a));
  EXPECT_FALSE(encoder.SameAsLast(b));
  EXPECT_FALSE(encoder.SameAsLast(a));
  EXPECT_FALSE(encoder.SameAsLast(TestPicture(16, 8)));  // another size
}

TEST(FrameEncoder, OddSizedVideoIsPaddedToEven) {
  const int w = 63, h = 47;
  FrameEncoder encoder;
  EncodingOptions e;
  e.format = ImageFormat::kH264;
  e.video_encoders = {"libx264"};
  const std::vector<uint8_t> picture = TestPicture(w, h);
  auto image = encoder.Encode(e, 30.0f, picture, {}, w, h, false);
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_TRUE(image->key_frame);
  auto decoder = VideoDecoder::Open(VideoCodec::kH264);
  ASSERT_TRUE(decoder.ok());
  auto decoded = (*decoder)->Decode(
      {reinterpret_cast<const uint8_t*>(image->bytes.data()), image->bytes.size()});
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_EQ(decoded->width, 64);
  EXPECT_EQ(decoded->height, 48);
  EXPECT_GE(Psnr(picture, decoded->rgba, w, h, decoded->width), 30.0);
}

TEST(FrameEncoder, HoldsBackOnlyUnchangedFramesWithoutNews) {
  using Clock = FrameEncoder::Clock;
  const Clock::time_point t0 = Clock::now();
  FrameEncoder encoder;
  EncodedFrame sent;
  sent.last_update_seq = 3;
  sent.stats = {{"update_complete", 1.0}};
  encoder.MarkSent(sent, t0);
  EncodedFrame still = sent;
  still.unchanged = true;
  EXPECT_TRUE(encoder.HoldBack(still, t0 + std::chrono::milliseconds(100)));
  // A keep-alive once the period has passed.
  EXPECT_FALSE(encoder.HoldBack(still, t0 + kKeepAlivePeriod));
  // An update's echo goes out at once, even when the picture is the same.
  EncodedFrame echo = still;
  echo.last_update_seq = 4;
  EXPECT_FALSE(encoder.HoldBack(echo, t0 + std::chrono::milliseconds(100)));
  // So does a change of update_complete (a background update finished).
  EncodedFrame completed = still;
  completed.stats = {{"update_complete", 0.0}};
  EXPECT_FALSE(encoder.HoldBack(completed, t0 + std::chrono::milliseconds(100)));
  // And any frame with a new picture.
  EncodedFrame changed = sent;
  EXPECT_FALSE(encoder.HoldBack(changed, t0 + std::chrono::milliseconds(100)));
}

}  // namespace video_encoder_test
}  // namespace gistream
