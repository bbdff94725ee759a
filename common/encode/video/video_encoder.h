// A zero-latency video encoder over libavcodec, one per session view: RGBA
// frames in, one access unit out per frame (no B-frames, no lookahead, so
// every frame comes out as soon as it goes in). H.264 and HEVC come out as
// Annex-B byte streams (start codes, SPS/PPS/VPS repeated before every key
// frame); AV1 as low-overhead OBUs (a sequence header before every key
// frame). The hardware encoder (NVENC) is tried first and the software one
// (libx264, libx265, libaom-av1 in realtime mode) used when it does not
// open (no NVIDIA GPU or driver).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "util/status.h"

namespace gistream {

enum class VideoCodec { kH264, kHevc, kAv1 };

const char* VideoCodecName(VideoCodec codec);  // "H264", "HEVC", "AV1"

struct VideoEncoderOptions {
  VideoCodec codec = VideoCodec::kH264;
  int width = 0;      // even
  int height = 0;     // even
  float fps = 30.0f;  // nominal rate, for rate control
  // Target bitrate in kbit/s; 0: constant quality at `crf`.
  uint32_t bitrate_kbps = 0;
  int crf = 23;  // x264 scale 1..51 (lower is better); also NVENC's cq
  // A key frame at least every this many encoded frames (and on request).
  uint32_t key_frame_interval = 120;
  // Only libavcodec encoders named here are tried (tests pin libx264);
  // empty: hardware first, then software.
  std::vector<std::string> encoders;
};

// The libavcodec encoder names tried for `codec`, in order of preference.
std::vector<std::string> VideoEncoderCandidates(VideoCodec codec);

// OK when some encoder for `codec` (of `encoders`, default: the
// candidates) opens on this machine (tried once per codec, list and process,
// at a small size); FAILED_PRECONDITION naming `field` and the encoders
// tried otherwise.
absl::Status CheckVideoEncoderAvailable(VideoCodec codec, const std::string& field,
                                        const std::vector<std::string>& encoders = {});

struct EncodedAccessUnit {
  std::string bytes;
  bool key_frame = false;
};

class VideoEncoder {
 public:
  static absl::StatusOr<std::unique_ptr<VideoEncoder>> Open(const VideoEncoderOptions& options);
  ~VideoEncoder();
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  // rgba: width * height * 4 bytes, sRGB, top row first. `key_frame`
  // forces an IDR / key frame.
  absl::StatusOr<EncodedAccessUnit> Encode(std::span<const uint8_t> rgba, bool key_frame);

  const std::string& encoder_name() const;  // e.g. "libx264", "h264_nvenc"
  const VideoEncoderOptions& options() const;

 private:
  struct State;
  explicit VideoEncoder(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace gistream
