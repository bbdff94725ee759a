#include "encode/video/video_encoder.h"

#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <map>
#include <mutex>
#include <utility>

#include "encode/video/av_handles.h"
#include "encode/video/yuv.h"
#include "util/log.h"

extern "C" {
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
}

namespace gistream {
namespace {

std::string AvError(int code) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, buf, sizeof buf);
  return buf;
}

// libavcodec (and x264 through it) log to stderr by default; route its
// lines into our log at debug level, once per process. Our own code logs
// which encoder opened and why others did not.
void AvLogCallback(void* avcl, int level, const char* fmt, va_list args) {
  if (level > AV_LOG_WARNING || !LogEnabled(LogLevel::kDebug)) return;
  char line[1024];
  int print_prefix = 1;
  av_log_format_line2(avcl, level, fmt, args, line, sizeof line, &print_prefix);
  std::string text(line);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  if (!text.empty()) Log(LogLevel::kDebug, absl::StrCat("libavcodec: ", text));
}

void RouteAvLogOnce() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_callback(AvLogCallback); });
}

bool IsNvenc(std::string_view name) { return name.find("nvenc") != std::string_view::npos; }

// Owns the options dictionary avcodec_open2 consumes (and may leave
// entries in).
struct Dict {
  AVDictionary* d = nullptr;
  Dict() = default;
  Dict(const Dict&) = delete;
  Dict& operator=(const Dict&) = delete;
  ~Dict() { av_dict_free(&d); }
};

// Zero-latency settings per encoder family, plus rate control.
void Configure(const VideoEncoderOptions& o, std::string_view name, AVCodecContext* ctx,
               AVDictionary** dict) {
  const int fps = std::max(1, int(std::lround(o.fps)));
  ctx->width = o.width;
  ctx->height = o.height;
  ctx->pix_fmt = AV_PIX_FMT_YUV420P;
  ctx->time_base = AVRational{1, fps};
  ctx->framerate = AVRational{fps, 1};
  ctx->gop_size = int(std::max<uint32_t>(1, o.key_frame_interval));
  ctx->max_b_frames = 0;
  ctx->color_range = AVCOL_RANGE_MPEG;
  ctx->colorspace = AVCOL_SPC_BT709;
  ctx->color_primaries = AVCOL_PRI_BT709;
  ctx->color_trc = AVCOL_TRC_IEC61966_2_1;  // the pixels are sRGB-encoded
  if (o.bitrate_kbps > 0) {
    ctx->bit_rate = int64_t(o.bitrate_kbps) * 1000;
    ctx->rc_max_rate = ctx->bit_rate;
    // A VBV of four frames' worth: rate control may not build up more delay.
    ctx->rc_buffer_size = int(std::min<int64_t>(ctx->bit_rate * 4 / fps, INT32_MAX));
  }
  const std::string crf = std::to_string(o.crf);
  if (name == "libx264" || name == "libx265") {
    av_dict_set(dict, "preset", "veryfast", 0);
    av_dict_set(dict, "tune", "zerolatency", 0);  // no lookahead, no frame threads
    av_dict_set(dict, "forced-idr", "1", 0);
    if (o.bitrate_kbps == 0) av_dict_set(dict, "crf", crf.c_str(), 0);
    if (name == "libx265") av_dict_set(dict, "x265-params", "log-level=error", 0);
  } else if (IsNvenc(name)) {
    av_dict_set(dict, "preset", "p1", 0);
    av_dict_set(dict, "tune", "ull", 0);
    av_dict_set(dict, "zerolatency", "1", 0);
    av_dict_set(dict, "delay", "0", 0);
    av_dict_set(dict, "rc-lookahead", "0", 0);
    av_dict_set(dict, "forced-idr", "1", 0);
    if (o.bitrate_kbps > 0) {
      av_dict_set(dict, "rc", "cbr", 0);
    } else {
      av_dict_set(dict, "rc", "vbr", 0);
      av_dict_set(dict, "cq", crf.c_str(), 0);
    }
  } else if (name == "libaom-av1") {
    // CRF on AV1's 0..63 scale, scaled from x264's 0..51.
    const std::string av1_crf = std::to_string(int(std::lround(o.crf * 63.0 / 51.0)));
    av_dict_set(dict, "usage", "realtime", 0);
    av_dict_set(dict, "cpu-used", "8", 0);
    av_dict_set(dict, "lag-in-frames", "0", 0);
    if (o.bitrate_kbps == 0) av_dict_set(dict, "crf", av1_crf.c_str(), 0);
  }
}

}  // namespace

const char* VideoCodecName(VideoCodec codec) {
  switch (codec) {
    case VideoCodec::kH264: return "H264";
    case VideoCodec::kHevc: return "HEVC";
    case VideoCodec::kAv1: return "AV1";
  }
  return "?";
}

std::vector<std::string> VideoEncoderCandidates(VideoCodec codec) {
  switch (codec) {
    case VideoCodec::kH264: return {"h264_nvenc", "libx264"};
    case VideoCodec::kHevc: return {"hevc_nvenc", "libx265"};
    // Not libsvtav1: through FFmpeg 5.1 it returns no packet before the
    // end of the stream (measured), which a live stream cannot wait for.
    case VideoCodec::kAv1: return {"av1_nvenc", "libaom-av1"};
  }
  return {};
}

struct VideoEncoder::State {
  VideoEncoderOptions options;
  std::string name;
  av::CodecContextPtr ctx;
  av::FramePtr frame;
  av::PacketPtr packet;
  int64_t next_pts = 0;
};

VideoEncoder::VideoEncoder(std::unique_ptr<State> state) : state_(std::move(state)) {}
VideoEncoder::~VideoEncoder() {
  // Drain before freeing (some encoders' deinit expects the end of the
  // stream).
  if (state_ && state_->ctx && avcodec_send_frame(state_->ctx.get(), nullptr) >= 0) {
    while (avcodec_receive_packet(state_->ctx.get(), state_->packet.get()) >= 0) {
      av_packet_unref(state_->packet.get());
    }
  }
}
const std::string& VideoEncoder::encoder_name() const { return state_->name; }
const VideoEncoderOptions& VideoEncoder::options() const { return state_->options; }

absl::StatusOr<std::unique_ptr<VideoEncoder>> VideoEncoder::Open(
    const VideoEncoderOptions& options) {
  RouteAvLogOnce();
  if (options.width <= 0 || options.height <= 0 || options.width % 2 != 0 ||
      options.height % 2 != 0) {
    return absl::InvalidArgumentError(absl::StrCat("width x height: ", options.width, "x",
                                                   options.height, " must be even for ",
                                                   VideoCodecName(options.codec)));
  }
  const std::vector<std::string> names =
      options.encoders.empty() ? VideoEncoderCandidates(options.codec) : options.encoders;
  std::vector<std::string> failures;
  for (const std::string& name : names) {
    const AVCodec* codec = avcodec_find_encoder_by_name(name.c_str());
    if (codec == nullptr) {
      failures.push_back(absl::StrCat(name, ": not in this libavcodec"));
      continue;
    }
    av::CodecContextPtr ctx(avcodec_alloc_context3(codec));
    if (!ctx) return absl::ResourceExhaustedError("video encoder: out of memory");
    Dict dict;
    Configure(options, name, ctx.get(), &dict.d);
    const int err = avcodec_open2(ctx.get(), codec, &dict.d);
    if (err < 0) {
      failures.push_back(absl::StrCat(name, ": ", AvError(err)));
      continue;
    }
    auto state = std::make_unique<State>();
    state->options = options;
    state->name = name;
    state->ctx = std::move(ctx);
    state->frame.reset(av_frame_alloc());
    state->packet.reset(av_packet_alloc());
    if (!state->frame || !state->packet) {
      return absl::ResourceExhaustedError("video encoder: out of memory");
    }
    state->frame->format = AV_PIX_FMT_YUV420P;
    state->frame->width = options.width;
    state->frame->height = options.height;
    if (int e = av_frame_get_buffer(state->frame.get(), 0); e < 0) {
      return absl::ResourceExhaustedError(absl::StrCat("video encoder frame: ", AvError(e)));
    }
    if (!failures.empty()) {
      Log(LogLevel::kDebug,
          absl::StrCat("video encoder ", name, " opened after ", absl::StrJoin(failures, "; ")));
    }
    return std::unique_ptr<VideoEncoder>(new VideoEncoder(std::move(state)));
  }
  return absl::FailedPreconditionError(absl::StrCat("no ", VideoCodecName(options.codec),
                                                    " encoder opens here (tried ",
                                                    absl::StrJoin(failures, "; "), ")"));
}

absl::StatusOr<EncodedAccessUnit> VideoEncoder::Encode(std::span<const uint8_t> rgba,
                                                       bool key_frame) {
  State& s = *state_;
  const size_t expected = size_t(s.options.width) * size_t(s.options.height) * 4;
  if (rgba.size() != expected) {
    return absl::InternalError(
        absl::StrCat("video encoder: got ", rgba.size(), " bytes, expected ", expected));
  }
  AVFrame* f = s.frame.get();
  if (int e = av_frame_make_writable(f); e < 0) {
    return absl::ResourceExhaustedError(absl::StrCat("video encoder frame: ", AvError(e)));
  }
  RgbaToYuv420(rgba, Yuv420Planes{s.options.width, s.options.height, f->data[0], f->data[1],
                                  f->data[2], f->linesize[0], f->linesize[1]});
  f->pts = s.next_pts++;
  f->pict_type = key_frame ? AV_PICTURE_TYPE_I : AV_PICTURE_TYPE_NONE;
  if (int e = avcodec_send_frame(s.ctx.get(), f); e < 0) {
    return absl::InternalError(absl::StrCat(s.name, ": send frame: ", AvError(e)));
  }
  EncodedAccessUnit out;
  for (;;) {
    const int e = avcodec_receive_packet(s.ctx.get(), s.packet.get());
    if (e == AVERROR(EAGAIN) || e == AVERROR_EOF) break;
    if (e < 0) return absl::InternalError(absl::StrCat(s.name, ": receive packet: ", AvError(e)));
    out.bytes.append(reinterpret_cast<const char*>(s.packet->data), size_t(s.packet->size));
    out.key_frame = out.key_frame || (s.packet->flags & AV_PKT_FLAG_KEY) != 0;
    av_packet_unref(s.packet.get());
  }
  if (out.bytes.empty()) {
    // Zero-latency settings make every encoder here emit one access unit
    // per frame; one that buffers would add latency, so say so.
    return absl::InternalError(absl::StrCat(s.name, ": no access unit for frame ", f->pts,
                                            " (the encoder buffers frames)"));
  }
  return out;
}

absl::Status CheckVideoEncoderAvailable(VideoCodec codec, const std::string& field,
                                        const std::vector<std::string>& encoders) {
  static std::mutex mutex;
  static std::map<std::pair<VideoCodec, std::string>, absl::Status> cache;
  std::lock_guard lock(mutex);
  const auto key = std::make_pair(codec, absl::StrJoin(encoders, ","));
  auto it = cache.find(key);
  if (it == cache.end()) {
    VideoEncoderOptions probe;
    probe.codec = codec;
    probe.width = 64;
    probe.height = 64;
    probe.encoders = encoders;
    absl::StatusOr<std::unique_ptr<VideoEncoder>> encoder = VideoEncoder::Open(probe);
    absl::Status status = encoder.status();
    if (encoder.ok()) {
      Log(LogLevel::kInfo, absl::StrCat(VideoCodecName(codec), " frames are encoded by ",
                                        (*encoder)->encoder_name()));
    }
    it = cache.emplace(key, status).first;
  }
  if (it->second.ok()) return absl::OkStatus();
  return absl::FailedPreconditionError(
      absl::StrCat(field, ": ", VideoCodecName(codec),
                   " is not available on this server: ", it->second.message()));
}

}  // namespace gistream
