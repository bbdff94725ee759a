#include "encode/video/video_decoder.h"

#include <absl/strings/str_cat.h>

#include <algorithm>

#include "encode/video/av_handles.h"
#include "encode/video/yuv.h"

extern "C" {
#include <libavutil/error.h>
#include <libavutil/pixfmt.h>
}

namespace gistream {
namespace {

std::string AvError(int code) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, buf, sizeof buf);
  return buf;
}

AVCodecID CodecId(VideoCodec codec) {
  switch (codec) {
    case VideoCodec::kH264: return AV_CODEC_ID_H264;
    case VideoCodec::kHevc: return AV_CODEC_ID_HEVC;
    case VideoCodec::kAv1: return AV_CODEC_ID_AV1;
  }
  return AV_CODEC_ID_NONE;
}

}  // namespace

struct VideoDecoder::State {
  av::CodecContextPtr ctx;
  av::FramePtr frame;
  av::PacketPtr packet;
};

VideoDecoder::VideoDecoder(std::unique_ptr<State> state) : state_(std::move(state)) {}
VideoDecoder::~VideoDecoder() = default;

absl::StatusOr<std::unique_ptr<VideoDecoder>> VideoDecoder::Open(VideoCodec codec) {
  const AVCodec* decoder = avcodec_find_decoder(CodecId(codec));
  if (decoder == nullptr) {
    return absl::FailedPreconditionError(
        absl::StrCat("no ", VideoCodecName(codec), " decoder in this libavcodec"));
  }
  auto state = std::make_unique<State>();
  state->ctx.reset(avcodec_alloc_context3(decoder));
  state->frame.reset(av_frame_alloc());
  state->packet.reset(av_packet_alloc());
  if (!state->ctx || !state->frame || !state->packet) {
    return absl::ResourceExhaustedError("video decoder: out of memory");
  }
  state->ctx->thread_count = 1;  // frame threads would delay output
  if (int e = avcodec_open2(state->ctx.get(), decoder, nullptr); e < 0) {
    return absl::FailedPreconditionError(absl::StrCat(decoder->name, ": ", AvError(e)));
  }
  return std::unique_ptr<VideoDecoder>(new VideoDecoder(std::move(state)));
}

absl::StatusOr<DecodedVideoFrame> VideoDecoder::Decode(std::span<const uint8_t> access_unit) {
  State& s = *state_;
  if (int e = av_new_packet(s.packet.get(), int(access_unit.size())); e < 0) {
    return absl::ResourceExhaustedError(absl::StrCat("video decoder packet: ", AvError(e)));
  }
  std::copy(access_unit.begin(), access_unit.end(), s.packet->data);
  const int sent = avcodec_send_packet(s.ctx.get(), s.packet.get());
  av_packet_unref(s.packet.get());
  if (sent < 0) return absl::InvalidArgumentError(absl::StrCat("decode: ", AvError(sent)));
  const int got = avcodec_receive_frame(s.ctx.get(), s.frame.get());
  if (got < 0)
    return absl::InvalidArgumentError(absl::StrCat("decode: no picture: ", AvError(got)));
  const AVFrame* f = s.frame.get();
  if (f->format != AV_PIX_FMT_YUV420P && f->format != AV_PIX_FMT_YUVJ420P) {
    av_frame_unref(s.frame.get());
    return absl::UnimplementedError(absl::StrCat("decode: pixel format ", f->format));
  }
  DecodedVideoFrame out;
  out.width = f->width;
  out.height = f->height;
  out.key_frame = f->key_frame != 0;
  out.rgba = Yuv420ToRgba(f->data[0], f->linesize[0], f->data[1], f->data[2], f->linesize[1],
                          f->width, f->height);
  if (f->linesize[1] != f->linesize[2]) {
    av_frame_unref(s.frame.get());
    return absl::UnimplementedError("decode: U and V planes of different strides");
  }
  av_frame_unref(s.frame.get());
  return out;
}

}  // namespace gistream
