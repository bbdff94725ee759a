// encode_bench: bitrate, encode time and quality of every frame format on
// the same rendered frames (docs/RESULTS.md, "Frame formats"). Renders the
// bundled Cornell box along the demo orbit (scenes/cornell_orbit.json's
// camera track) through the engine in PNG (the lossless reference), then
// encodes those RGBA frames as JPEG, PNG and each video format the
// libavcodec here has, one encoder per stream as the server keeps one per
// session. Prints a Markdown table: mean PSNR (RGB) and SSIM (luma, 8x8
// windows) against the lossless frames, kbit/s at 30 fps, median and p95
// encode ms per frame (RGB->YUV included for video).
//
//   build/encode_bench [--scenes DIR] [--frames N] [--sizes 320x240,1280x720,1920x1080]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <iostream>
#include <mutex>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <absl/strings/str_split.h>

#include "encode/encode.h"
#include "encode/video/video_decoder.h"
#include "encode/video/video_encoder.h"
#include "engine/engine.h"

namespace gistream {
namespace {

using Clock = std::chrono::steady_clock;

class QueueSink final : public FrameSink {
 public:
  void OnFrame(std::shared_ptr<const EncodedFrame> frame) override {
    std::lock_guard lock(mutex_);
    frames_.push_back(std::move(frame));
    cv_.notify_all();
  }
  void OnUpdateRejected(uint64_t, const absl::Status& s) override { Fail(s); }
  void OnSessionFailed(const absl::Status& s) override { Fail(s); }
  absl::StatusOr<std::shared_ptr<const EncodedFrame>> Next() {
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [&] { return !frames_.empty() || !failed_.ok(); });
    if (!failed_.ok()) return failed_;
    auto f = frames_.front();
    frames_.pop_front();
    return f;
  }

 private:
  void Fail(const absl::Status& s) {
    std::lock_guard lock(mutex_);
    failed_ = s;
    cv_.notify_all();
  }
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::shared_ptr<const EncodedFrame>> frames_;
  absl::Status failed_;
};

struct Picture {
  int w = 0, h = 0;
  std::vector<uint8_t> rgba;
};

double Psnr(const Picture& ref, const std::vector<uint8_t>& img, int stride_w) {
  double sum = 0.0;
  for (int y = 0; y < ref.h; ++y) {
    for (int x = 0; x < ref.w; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double d = double(ref.rgba[(size_t(y) * size_t(ref.w) + size_t(x)) * 4 + size_t(c)]) -
                         double(img[(size_t(y) * size_t(stride_w) + size_t(x)) * 4 + size_t(c)]);
        sum += d * d;
      }
    }
  }
  const double mse = sum / (3.0 * ref.w * ref.h);
  return mse == 0.0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

// Mean SSIM over non-overlapping 8x8 windows of Rec. 709 luma in [0, 1].
double Ssim(const Picture& ref, const std::vector<uint8_t>& img, int stride_w) {
  auto luma = [](const uint8_t* p) {
    return (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) / 255.0;
  };
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  double total = 0.0;
  int windows = 0;
  for (int wy = 0; wy + 8 <= ref.h; wy += 8) {
    for (int wx = 0; wx + 8 <= ref.w; wx += 8) {
      double ma = 0, mb = 0, va = 0, vb = 0, cov = 0;
      for (int y = wy; y < wy + 8; ++y) {
        for (int x = wx; x < wx + 8; ++x) {
          const double a = luma(&ref.rgba[(size_t(y) * size_t(ref.w) + size_t(x)) * 4]);
          const double b = luma(&img[(size_t(y) * size_t(stride_w) + size_t(x)) * 4]);
          ma += a, mb += b, va += a * a, vb += b * b, cov += a * b;
        }
      }
      ma /= 64, mb /= 64;
      va = va / 64 - ma * ma, vb = vb / 64 - mb * mb, cov = cov / 64 - ma * mb;
      total += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      ++windows;
    }
  }
  return windows ? total / windows : 1.0;
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(p * double(v.size() - 1) + 0.5))];
}

struct Row {
  std::string format;
  double psnr = 0, ssim = 0, kbps = 0, median_ms = 0, p95_ms = 0;
};

absl::StatusOr<std::vector<Picture>> RenderOrbit(Engine& engine, const std::string& scene, int w,
                                                 int h, int frames) {
  auto sink = std::make_shared<QueueSink>();
  SessionConfig config;
  config.scene = scene;
  config.width = uint32_t(w);
  config.height = uint32_t(h);
  config.pacing = Pacing::kOnRequest;
  config.encoding.format = ImageFormat::kPng;
  config.encoding.send_unchanged = true;
  auto session = engine.OpenSession(config, sink);
  if (!session.ok()) return session.status();
  std::vector<Picture> out;
  for (int i = 0; i < frames; ++i) {
    // scenes/cornell_orbit.json's camera_orbit track.
    const float t = frames > 1 ? float(i) / float(frames - 1) : 0.0f;
    const float deg = -104.0f + 28.0f * t;
    const float a = deg * std::numbers::pi_v<float> / 180.0f;
    const glm::vec3 target{0.278f, 0.274f, 0.28f};
    CameraUpdate camera;
    camera.look_at = LookAt{target + glm::vec3(1.08f * std::cos(a), 0.0f, 1.08f * std::sin(a)),
                            target,
                            {0.0f, 1.0f, 0.0f}};
    camera.yfov_degrees = 39.3f;
    if (absl::Status s = engine.PushUpdate(session->id, {uint64_t(i + 1), camera}); !s.ok())
      return s;
    if (absl::Status s = engine.RequestFrames(session->id, 1); !s.ok()) return s;
    auto frame = sink->Next();
    if (!frame.ok()) return frame.status();
    const std::string& bytes = (*frame)->image;
    auto decoded = DecodeImageBytes({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()});
    if (!decoded.ok()) return decoded.status();
    Picture p{decoded->width, decoded->height, {}};
    p.rgba.resize(decoded->rgba.size());
    for (size_t k = 0; k < p.rgba.size(); ++k)
      p.rgba[k] = uint8_t(std::lround(decoded->rgba[k] * 255.0f));
    out.push_back(std::move(p));
  }
  engine.CloseSession(session->id);
  return out;
}

Row MeasureImages(const std::string& name, const std::vector<Picture>& pics,
                  const std::function<absl::StatusOr<std::string>(const Picture&)>& encode) {
  Row row{name};
  std::vector<double> ms;
  double bytes = 0;
  for (const Picture& p : pics) {
    const auto t0 = Clock::now();
    auto encoded = encode(p);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (!encoded.ok()) {
      std::cerr << name << ": " << encoded.status() << "\n";
      return row;
    }
    bytes += double(encoded->size());
    auto decoded =
        DecodeImageBytes({reinterpret_cast<const uint8_t*>(encoded->data()), encoded->size()});
    std::vector<uint8_t> rgba(decoded->rgba.size());
    for (size_t k = 0; k < rgba.size(); ++k)
      rgba[k] = uint8_t(std::lround(decoded->rgba[k] * 255.0f));
    row.psnr += Psnr(p, rgba, p.w) / double(pics.size());
    row.ssim += Ssim(p, rgba, p.w) / double(pics.size());
  }
  row.kbps = bytes * 8.0 / 1000.0 * 30.0 / double(pics.size());
  row.median_ms = Percentile(ms, 0.5);
  row.p95_ms = Percentile(ms, 0.95);
  return row;
}

std::optional<Row> MeasureVideo(VideoCodec codec, const std::vector<std::string>& encoders, int crf,
                                const std::vector<Picture>& pics) {
  VideoEncoderOptions o;
  o.codec = codec;
  o.width = (pics[0].w + 1) & ~1;
  o.height = (pics[0].h + 1) & ~1;
  o.crf = crf;
  o.encoders = encoders;
  auto encoder = VideoEncoder::Open(o);
  if (!encoder.ok()) {
    std::cerr << VideoCodecName(codec) << ": " << encoder.status() << "\n";
    return std::nullopt;
  }
  auto decoder = VideoDecoder::Open(codec);
  if (!decoder.ok()) return std::nullopt;
  Row row{
      absl::StrCat(VideoCodecName(codec), " (", (*encoder)->encoder_name(), ", CRF ", crf, ")")};
  std::vector<double> ms;
  double bytes = 0;
  for (const Picture& p : pics) {
    const auto t0 = Clock::now();
    auto unit = (*encoder)->Encode(p.rgba, false);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (!unit.ok()) {
      std::cerr << row.format << ": " << unit.status() << "\n";
      return std::nullopt;
    }
    bytes += double(unit->bytes.size());
    auto decoded = (*decoder)->Decode(
        {reinterpret_cast<const uint8_t*>(unit->bytes.data()), unit->bytes.size()});
    if (!decoded.ok()) {
      std::cerr << row.format << ": " << decoded.status() << "\n";
      return std::nullopt;
    }
    row.psnr += Psnr(p, decoded->rgba, decoded->width) / double(pics.size());
    row.ssim += Ssim(p, decoded->rgba, decoded->width) / double(pics.size());
  }
  row.kbps = bytes * 8.0 / 1000.0 * 30.0 / double(pics.size());
  row.median_ms = Percentile(ms, 0.5);
  row.p95_ms = Percentile(ms, 0.95);
  return row;
}

int Main(int argc, char** argv) {
  std::string scenes = "scenes";
  int frames = 30;
  std::vector<std::pair<int, int>> sizes = {{320, 240}, {1280, 720}, {1920, 1080}};
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--scenes")
      scenes = value;
    else if (flag == "--frames")
      frames = std::max(2, std::atoi(value.c_str()));
    else if (flag == "--sizes") {
      sizes.clear();
      for (const auto& s : absl::StrSplit(value, ',')) {
        int w = 0, h = 0;
        if (std::sscanf(std::string(s).c_str(), "%dx%d", &w, &h) == 2) sizes.emplace_back(w, h);
      }
    } else {
      std::cerr << "usage: encode_bench [--scenes DIR] [--frames N] [--sizes WxH,...]\n";
      return 2;
    }
  }
  EngineOptions options;
  options.scene_dir = scenes;
  auto engine = Engine::Create(options);
  if (!engine.ok()) {
    std::cerr << engine.status() << "\n";
    return 1;
  }
  SceneSource source;
  source.name = "cornell_box";
  auto scene = (*engine)->LoadScene(source);
  if (!scene.ok()) {
    std::cerr << scene.status() << "\n";
    return 1;
  }
  std::cout << "renderer: " << (*engine)->device_info().renderer
            << "; CPU: " << (*engine)->device_info().cpu_model << " ("
            << (*engine)->device_info().cpu_threads << " threads); " << frames
            << " frames of the Cornell box orbit, direct solver\n\n";
  std::cout << "| size | format | PSNR dB | SSIM | kbit/s at 30 fps | encode ms median | p95 |\n"
            << "| --- | --- | ---: | ---: | ---: | ---: | ---: |\n";
  for (const auto& [w, h] : sizes) {
    auto pics = RenderOrbit(**engine, scene->id, w, h, frames);
    if (!pics.ok()) {
      std::cerr << pics.status() << "\n";
      return 1;
    }
    std::vector<Row> rows;
    for (int q : {75, 90}) {
      rows.push_back(MeasureImages(absl::StrCat("JPEG q", q), *pics, [q](const Picture& p) {
        return EncodeJpeg(p.rgba, p.w, p.h, q);
      }));
    }
    rows.push_back(
        MeasureImages("PNG", *pics, [](const Picture& p) { return EncodePng(p.rgba, p.w, p.h); }));
    for (int crf : {18, 23, 28}) {
      if (auto r = MeasureVideo(VideoCodec::kH264, {"libx264"}, crf, *pics)) rows.push_back(*r);
    }
    if (auto r = MeasureVideo(VideoCodec::kH264, {"h264_nvenc"}, 23, *pics)) rows.push_back(*r);
    if (auto r = MeasureVideo(VideoCodec::kHevc, {}, 23, *pics)) rows.push_back(*r);
    if (auto r = MeasureVideo(VideoCodec::kAv1, {}, 23, *pics)) rows.push_back(*r);
    for (const Row& r : rows) {
      char line[256];
      std::snprintf(line, sizeof line, "| %dx%d | %s | %.1f | %.4f | %.0f | %.2f | %.2f |\n", w, h,
                    r.format.c_str(), r.psnr, r.ssim, r.kbps, r.median_ms, r.p95_ms);
      std::cout << line << std::flush;
    }
  }
  (*engine)->Shutdown();
  return 0;
}

}  // namespace
}  // namespace gistream

int main(int argc, char** argv) { return gistream::Main(argc, argv); }
