// Frames through the real engine in video formats and the unchanged-frame
// rule (issue 16): an H.264 frame decodes with libavcodec to within 30 dB
// PSNR of the PNG of the same frame; a still scene sends no repeated image
// (on request: answers without an image; continuous: keep-alives only); a
// key-frame request yields a key frame with its image; an encoder the
// server lacks is FAILED_PRECONDITION naming encoding.format.
#include <cmath>
#include <condition_variable>
#include <deque>
#include <mutex>

#include <gtest/gtest.h>

#include "encode/encode.h"
#include "encode/video/video_decoder.h"
#include "support/frame_queue.h"
#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace video_frames_test {

using testing::BundledCopy;
using testing::SharedEngine;

using QueueSink = testing::FrameQueue;

constexpr uint32_t kSize = 128;

SessionConfig Config(const std::string& scene, ImageFormat format, Pacing pacing) {
  SessionConfig c;
  c.scene = scene;
  c.width = kSize;
  c.height = kSize;
  c.params = {{"area_samples", "16"}, {"shadow_res", "128"}};
  c.encoding.format = format;
  c.encoding.video_encoders = {"libx264"};  // the same encoder with and without a GPU
  c.pacing = pacing;
  c.refine_samples = 1;  // a still picture from the first frame on
  return c;
}

std::span<const uint8_t> Bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// PSNR over R, G, B (8-bit values).
double Psnr(const std::vector<uint8_t>& a, const std::vector<float>& b01) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (i % 4 == 3) continue;
    const double d = double(a[i]) - std::round(double(b01[i]) * 255.0);
    sum += d * d;
    ++n;
  }
  const double mse = sum / double(n);
  return mse == 0.0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

class VideoFramesTest : public ::testing::Test {
 protected:
  std::shared_ptr<const EncodedFrame> Request(const SessionId& id, QueueSink& sink) {
    EXPECT_TRUE(SharedEngine().RequestFrames(id, 1).ok());
    return sink.Next();
  }
  BundledCopy scene_{"cornell_box.gltf"};
};

TEST_F(VideoFramesTest, H264DecodesCloseToThePngOfTheSameFrame) {
  auto h264_sink = std::make_shared<QueueSink>();
  auto png_sink = std::make_shared<QueueSink>();
  auto h264 = SharedEngine().OpenSession(
      Config(scene_.id(), ImageFormat::kH264, Pacing::kOnRequest), h264_sink);
  auto png = SharedEngine().OpenSession(Config(scene_.id(), ImageFormat::kPng, Pacing::kOnRequest),
                                        png_sink);
  ASSERT_TRUE(h264.ok()) << h264.status();
  ASSERT_TRUE(png.ok()) << png.status();
  auto video_frame = Request(h264->id, *h264_sink);
  auto png_frame = Request(png->id, *png_sink);
  ASSERT_TRUE(video_frame && png_frame);
  EXPECT_EQ(video_frame->format, ImageFormat::kH264);
  EXPECT_TRUE(video_frame->key_frame);
  EXPECT_FALSE(video_frame->unchanged);

  auto decoder = VideoDecoder::Open(VideoCodec::kH264);
  ASSERT_TRUE(decoder.ok()) << decoder.status();
  auto decoded = (*decoder)->Decode(Bytes(video_frame->image));
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  auto reference = DecodeImageBytes(Bytes(png_frame->image));
  ASSERT_TRUE(reference.ok()) << reference.status();
  ASSERT_EQ(decoded->width, reference->width);
  ASSERT_EQ(decoded->height, reference->height);
  // x264 at CRF 23 with 4:2:0 chroma: the red and green walls' edges and
  // the shadow boundaries carry most of the error. 30 dB is an RMS error
  // of 8/255, about what JPEG quality 75 gives on this picture.
  const double psnr = Psnr(decoded->rgba, reference->rgba);
  EXPECT_GE(psnr, 30.0);
  testing::RecordMeasurement("h264_psnr_db", psnr);
  testing::RecordMeasurement("h264_bytes", double(video_frame->image.size()));
  testing::RecordMeasurement("png_bytes", double(png_frame->image.size()));
  SharedEngine().CloseSession(h264->id);
  SharedEngine().CloseSession(png->id);
}

TEST_F(VideoFramesTest, AStillSceneSendsNoRepeatedImagesAndKeyFramesComeOnRequest) {
  auto sink = std::make_shared<QueueSink>();
  auto session =
      SharedEngine().OpenSession(Config(scene_.id(), ImageFormat::kH264, Pacing::kOnRequest), sink);
  ASSERT_TRUE(session.ok()) << session.status();
  auto decoder = VideoDecoder::Open(VideoCodec::kH264);
  ASSERT_TRUE(decoder.ok());

  auto first = Request(session->id, *sink);
  ASSERT_TRUE(first);
  EXPECT_FALSE(first->image.empty());
  ASSERT_TRUE((*decoder)->Decode(Bytes(first->image)).ok());
  // Five requests with nothing changed: five answers, none with an image,
  // and nothing was encoded for them.
  constexpr int kStill = 5;
  int with_image = 0;
  for (int i = 0; i < kStill; ++i) {
    auto f = Request(session->id, *sink);
    ASSERT_TRUE(f);
    with_image += f->image.empty() ? 0 : 1;
    EXPECT_TRUE(f->unchanged);
    EXPECT_FALSE(f->key_frame);
    EXPECT_TRUE(testing::StageSkipped(*f, "encode"));
  }
  EXPECT_EQ(with_image, 0);

  // A key frame on request, although nothing changed; it decodes.
  ASSERT_TRUE(SharedEngine().RequestKeyFrame(session->id).ok());
  auto key = Request(session->id, *sink);
  ASSERT_TRUE(key);
  EXPECT_TRUE(key->key_frame);
  EXPECT_FALSE(key->unchanged);
  EXPECT_FALSE(key->image.empty());
  auto decoded = (*decoder)->Decode(Bytes(key->image));
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_TRUE(decoded->key_frame);

  // A camera change: a delta frame, not a key frame, that decodes after it.
  CameraUpdate camera;
  camera.yfov_degrees = 30.0f;
  ASSERT_TRUE(SharedEngine().PushUpdate(session->id, {1, camera}).ok());
  auto moved = Request(session->id, *sink);
  ASSERT_TRUE(moved);
  EXPECT_FALSE(moved->unchanged);
  EXPECT_FALSE(moved->key_frame);
  EXPECT_TRUE((*decoder)->Decode(Bytes(moved->image)).ok());
  SharedEngine().CloseSession(session->id);
}

TEST_F(VideoFramesTest, AContinuousStillSceneSendsOnlyKeepAlives) {
  auto sink = std::make_shared<QueueSink>();
  SessionConfig config = Config(scene_.id(), ImageFormat::kJpeg, Pacing::kContinuous);
  config.max_fps = 60.0f;
  config.width = config.height = 32;
  auto session = SharedEngine().OpenSession(config, sink);
  ASSERT_TRUE(session.ok()) << session.status();
  auto first = sink->Next();
  ASSERT_TRUE(first);
  EXPECT_FALSE(first->image.empty());
  for (int i = 0; i < 2; ++i) {
    auto f = sink->Next();
    ASSERT_TRUE(f);
    EXPECT_TRUE(f->unchanged);
    EXPECT_TRUE(f->image.empty());
    // Keep-alives, about a second apart: the view rests in between
    // (engine_rest_test.cpp).
    EXPECT_GT(f->frame_number, first->frame_number + uint64_t(i));
  }
  SharedEngine().CloseSession(session->id);
}

TEST_F(VideoFramesTest, AnEncoderTheServerLacksIsFailedPrecondition) {
  SessionConfig config = Config(scene_.id(), ImageFormat::kH264, Pacing::kOnRequest);
  config.encoding.video_encoders = {"no_such_encoder"};
  auto session = SharedEngine().OpenSession(config, std::make_shared<QueueSink>());
  EXPECT_EQ(session.status().code(), absl::StatusCode::kFailedPrecondition) << session.status();
  EXPECT_NE(session.status().message().find("encoding.format"), std::string::npos);
}

}  // namespace video_frames_test
}  // namespace gistream
