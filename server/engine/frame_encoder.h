// A session view's frame encoding: JPEG/PNG/EXR per frame, or one video
// encoder (H.264/HEVC/AV1, encode/video/) that lives as long as the view and
// is reopened when the frame size changes. It also decides what is not
// worth sending: a frame whose pixels (the readback, before encoding) equal
// the previous frame's is "unchanged" and carries no image; a continuous
// session holds such frames back unless they tell the client something new
// (a newer update sequence number, or the solver's update_complete stat
// changed: a client waiting for its update's echo gets it at once even when
// the update changed nothing visible), or as keep-alives, once per
// kKeepAlivePeriod.
// Render thread only.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "encode/video/video_encoder.h"
#include "engine/engine.h"
#include "util/status.h"

namespace gistream {

inline constexpr std::chrono::milliseconds kKeepAlivePeriod{1000};

bool IsVideoFormat(ImageFormat format);

// Checks the fields of `encoding` the translation layer cannot: ranges and
// whether this server has an encoder for the format (FAILED_PRECONDITION
// naming encoding.format when it has none).
absl::Status ValidateEncoding(const EncodingOptions& encoding);

// CPU bytes a view of `width` x `height` holds at most to produce a frame
// in `format`: the readback and the copy SameAsLast keeps (RGBA8, or RGBA
// float for EXR), the encoder's output buffers, and for video the padded
// copy and the encoder's own frames (an estimate for libx264 at veryfast
// with zerolatency: about six 4:2:0 frames with their lowres planes).
uint64_t EstimateFrameBytes(uint32_t width, uint32_t height, ImageFormat format);

struct EncodedImage {
  std::string bytes;
  bool key_frame = true;  // every JPEG/PNG/EXR frame is one
};

class FrameEncoder {
 public:
  using Clock = std::chrono::steady_clock;

  // True when `pixels` equal the last frame's pixels (same size); keeps a
  // copy of them either way.
  bool SameAsLast(std::span<const uint8_t> pixels);

  // ldr: RGBA8 for JPEG/PNG/video; hdr: RGBA float for EXR. `key_frame`
  // forces a video key frame. `fps` sizes the video rate control.
  absl::StatusOr<EncodedImage> Encode(const EncodingOptions& encoding, float fps,
                                      std::span<const uint8_t> ldr, std::span<const float> hdr,
                                      int width, int height, bool key_frame);

  // Whether a continuous session keeps `frame` to itself: unchanged, with
  // the same update sequence number and update_complete stat as the last
  // frame sent, and a frame went out within kKeepAlivePeriod.
  bool HoldBack(const EncodedFrame& frame, Clock::time_point now) const;
  // `frame` went to the client at `now`.
  void MarkSent(const EncodedFrame& frame, Clock::time_point now);
  // When the last frame went out (the epoch before the first).
  Clock::time_point last_sent() const { return last_sent_; }

  // The libavcodec encoder in use ("" before the first video frame).
  std::string video_encoder_name() const;

 private:
  std::vector<uint8_t> last_pixels_;
  std::unique_ptr<VideoEncoder> video_;
  std::vector<uint8_t> padded_;  // odd sizes, padded to even for 4:2:0
  // The last frame sent: when, its update sequence number, update_complete.
  Clock::time_point last_sent_{};
  uint64_t sent_seq_ = 0;
  double sent_complete_ = -1.0;
};

}  // namespace gistream
