// Decodes the access units VideoEncoder makes back to RGBA (libavcodec's
// own decoders), for tests and measurement tools; the server never decodes.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "encode/video/video_encoder.h"
#include "util/status.h"

namespace gistream {

struct DecodedVideoFrame {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // sRGB, top row first
  bool key_frame = false;
};

class VideoDecoder {
 public:
  static absl::StatusOr<std::unique_ptr<VideoDecoder>> Open(VideoCodec codec);
  ~VideoDecoder();
  VideoDecoder(const VideoDecoder&) = delete;
  VideoDecoder& operator=(const VideoDecoder&) = delete;

  // One access unit in, the picture it completes out (the encoders here
  // have no delay, so there is one per access unit).
  absl::StatusOr<DecodedVideoFrame> Decode(std::span<const uint8_t> access_unit);

 private:
  struct State;
  explicit VideoDecoder(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace gistream
