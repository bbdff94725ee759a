#include "engine/frame_encoder.h"

#include <algorithm>
#include <cstring>

#include "encode/encode.h"
#include "util/log.h"

namespace gistream {
namespace {

VideoCodec CodecOf(ImageFormat format) {
  switch (format) {
    case ImageFormat::kHevc: return VideoCodec::kHevc;
    case ImageFormat::kAv1: return VideoCodec::kAv1;
    default: return VideoCodec::kH264;
  }
}

// Copies an odd-sized RGBA image into an even-sized one, repeating the
// last column and row.
void PadToEven(std::span<const uint8_t> rgba, int w, int h, int pw, int ph,
               std::vector<uint8_t>& out) {
  out.resize(size_t(pw) * size_t(ph) * 4);
  for (int y = 0; y < ph; ++y) {
    const uint8_t* src = rgba.data() + size_t(std::min(y, h - 1)) * size_t(w) * 4;
    uint8_t* dst = out.data() + size_t(y) * size_t(pw) * 4;
    std::memcpy(dst, src, size_t(w) * 4);
    for (int x = w; x < pw; ++x) std::memcpy(dst + 4 * x, src + 4 * (w - 1), 4);
  }
}

}  // namespace

bool IsVideoFormat(ImageFormat format) {
  return format == ImageFormat::kH264 || format == ImageFormat::kHevc ||
         format == ImageFormat::kAv1;
}

uint64_t EstimateFrameBytes(uint32_t width, uint32_t height, ImageFormat format) {
  uint64_t per_pixel = 0;
  switch (format) {
    case ImageFormat::kJpeg:  // readback 4, copy 4, JpegBound's 6, the output 6
      per_pixel = 20;
      break;
    case ImageFormat::kPng:  // readback 4, copy 4, the output (raw size and deflate's margin)
      per_pixel = 16;
      break;
    case ImageFormat::kExr:  // readback 16, copy 16, RGB for the writer 12, output 12 twice
      per_pixel = 72;
      break;
    case ImageFormat::kH264:
    case ImageFormat::kHevc:
    case ImageFormat::kAv1:  // readback, copy, padded copy 4 each; 4:2:0 input 1.5; frames
      per_pixel = 40;
      break;
  }
  return uint64_t(width) * uint64_t(height) * per_pixel;
}

absl::Status ValidateEncoding(const EncodingOptions& e) {
  if (!IsVideoFormat(e.format)) return absl::OkStatus();
  if (e.crf < 1 || e.crf > 51) {
    return absl::InvalidArgumentError(
        absl::StrCat("encoding.crf: ", e.crf, " is out of range [1, 51]"));
  }
  if (e.bitrate_kbps > 1'000'000) {
    return absl::InvalidArgumentError(
        absl::StrCat("encoding.bitrate_kbps: ", e.bitrate_kbps, " is out of range [0, 1000000]"));
  }
  if (e.key_frame_interval < 1 || e.key_frame_interval > 100'000) {
    return absl::InvalidArgumentError(absl::StrCat(
        "encoding.key_frame_interval: ", e.key_frame_interval, " is out of range [1, 100000]"));
  }
  return CheckVideoEncoderAvailable(CodecOf(e.format), "encoding.format", e.video_encoders);
}

namespace {
double UpdateComplete(const EncodedFrame& frame) {
  for (const auto& [name, value] : frame.stats) {
    if (name == "update_complete") return value;
  }
  return -1.0;
}
}  // namespace

bool FrameEncoder::HoldBack(const EncodedFrame& frame, Clock::time_point now) const {
  return frame.unchanged && frame.last_update_seq == sent_seq_ &&
         UpdateComplete(frame) == sent_complete_ && now - last_sent_ < kKeepAlivePeriod;
}

void FrameEncoder::MarkSent(const EncodedFrame& frame, Clock::time_point now) {
  last_sent_ = now;
  sent_seq_ = frame.last_update_seq;
  sent_complete_ = UpdateComplete(frame);
}

bool FrameEncoder::SameAsLast(std::span<const uint8_t> pixels) {
  const bool same = last_pixels_.size() == pixels.size() &&
                    std::equal(pixels.begin(), pixels.end(), last_pixels_.begin());
  if (!same) last_pixels_.assign(pixels.begin(), pixels.end());
  return same;
}

std::string FrameEncoder::video_encoder_name() const {
  return video_ ? video_->encoder_name() : std::string();
}

absl::StatusOr<EncodedImage> FrameEncoder::Encode(const EncodingOptions& enc, float fps,
                                                  std::span<const uint8_t> ldr,
                                                  std::span<const float> hdr, int width, int height,
                                                  bool key_frame) {
  EncodedImage out;
  switch (enc.format) {
    case ImageFormat::kExr: {
      GS_ASSIGN_OR_RETURN(out.bytes, EncodeExr(hdr, width, height));
      return out;
    }
    case ImageFormat::kPng: {
      GS_ASSIGN_OR_RETURN(out.bytes, EncodePng(ldr, width, height));
      return out;
    }
    case ImageFormat::kJpeg: {
      GS_ASSIGN_OR_RETURN(out.bytes, EncodeJpeg(ldr, width, height, enc.quality));
      return out;
    }
    default: break;
  }
  const int pw = (width + 1) & ~1, ph = (height + 1) & ~1;
  if (!video_ || video_->options().width != pw || video_->options().height != ph) {
    VideoEncoderOptions options;
    options.codec = CodecOf(enc.format);
    options.width = pw;
    options.height = ph;
    options.fps = fps;
    options.bitrate_kbps = enc.bitrate_kbps;
    options.crf = enc.crf;
    options.key_frame_interval = enc.key_frame_interval;
    options.encoders = enc.video_encoders;
    video_.reset();
    GS_ASSIGN_OR_RETURN(video_, VideoEncoder::Open(options));
    Log(LogLevel::kInfo, absl::StrCat(VideoCodecName(options.codec), " ", pw, "x", ph,
                                      " encoded by ", video_->encoder_name()));
  }
  std::span<const uint8_t> pixels = ldr;
  if (pw != width || ph != height) {
    PadToEven(ldr, width, height, pw, ph, padded_);
    pixels = padded_;
  }
  GS_ASSIGN_OR_RETURN(EncodedAccessUnit unit, video_->Encode(pixels, key_frame));
  out.bytes = std::move(unit.bytes);
  out.key_frame = unit.key_frame;
  return out;
}

}  // namespace gistream
