// `gistream eval`'s pure parts: metrics with known values, the spec parser,
// the cache key, the plot.
#include <cmath>

#include <gtest/gtest.h>

#include "encode/encode.h"
#include "eval_spec.h"
#include "util/image_metrics.h"
#include "plot.h"

namespace gistream::client {
namespace eval_test {

RgbaImage Constant(int w, int h, float v) {
  RgbaImage img{w, h, std::vector<float>(size_t(w * h * 4), v)};
  for (size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 1.0f;
  return img;
}

RgbaImage Checker(int w, int h) {
  RgbaImage img = Constant(w, h, 0.0f);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float v = ((x / 2 + y / 2) % 2) ? 0.8f : 0.1f;
      for (int c = 0; c < 3; ++c) img.rgba[size_t((y * w + x) * 4 + c)] = v;
    }
  }
  return img;
}

TEST(Metrics, IdenticalImagesHaveNoError) {
  const RgbaImage a = Checker(16, 16);
  auto e = CompareImages(a, a);
  ASSERT_TRUE(e.ok()) << e.status();
  EXPECT_EQ(e->rel_mse, 0.0);
  EXPECT_EQ(e->rmse, 0.0);
  EXPECT_NEAR(e->ssim, 1.0, 1e-12);
  EXPECT_EQ(e->nonfinite_fraction, 0.0);
}

TEST(Metrics, ConstantOffsetGivesTheClosedForm) {
  // relMSE = d^2 / (r^2 + 0.01), RMSE = d.
  const float r = 0.5f, d = 0.2f;
  auto e = CompareImages(Constant(8, 8, r + d), Constant(8, 8, r));
  ASSERT_TRUE(e.ok());
  EXPECT_NEAR(e->rel_mse, double(d) * d / (double(r) * r + 0.01), 1e-6);
  EXPECT_NEAR(e->rmse, d, 1e-6);
}

TEST(Metrics, SsimDropsForNoise) {
  const RgbaImage a = Checker(16, 16);
  RgbaImage b = a;
  for (size_t i = 0; i < b.rgba.size(); i += 7) b.rgba[i] = 0.5f;
  auto e = CompareImages(b, a);
  ASSERT_TRUE(e.ok());
  EXPECT_LT(e->ssim, 0.95);
  EXPECT_GT(e->rel_mse, 0.0);
}

TEST(Metrics, SsimDropsForAShiftedCopy) {
  const RgbaImage a = Checker(16, 16);
  RgbaImage b = Constant(16, 16, 0.0f);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      const int sx = (x + 1) % 16;  // one pixel to the left, wrapping
      for (int c = 0; c < 4; ++c) {
        b.rgba[size_t((y * 16 + x) * 4 + c)] = a.rgba[size_t((y * 16 + sx) * 4 + c)];
      }
    }
  }
  auto e = CompareImages(b, a);
  ASSERT_TRUE(e.ok());
  EXPECT_LT(e->ssim, 0.9);
  EXPECT_GT(e->ssim, -1.0);
}

TEST(Metrics, ToneMapMatchesTheServersDisplayTransform) {
  EXPECT_EQ(ToneMappedLuminance(0, 0, 0), 0.0f);
  // ACES fit at 1: 2.54 / 3.16 = 0.80380; sRGB OETF: 0.90823. Grey keeps it
  // (the Rec. 709 weights sum to 1).
  EXPECT_NEAR(ToneMappedLuminance(1, 1, 1), 0.90823f, 1e-4f);
  EXPECT_NEAR(ToneMappedLuminance(1e6f, 1e6f, 1e6f), 1.0f, 1e-5f);  // clamped
  EXPECT_NEAR(ToneMappedLuminance(0, 1e6f, 0), 0.7152f, 1e-5f);
}

TEST(Metrics, NonFinitePixelsAreCounted) {
  RgbaImage a = Constant(4, 4, 1.0f);
  a.rgba[0] = std::nanf("");
  a.rgba[5] = INFINITY;
  auto e = CompareImages(a, Constant(4, 4, 1.0f));
  ASSERT_TRUE(e.ok());
  EXPECT_DOUBLE_EQ(e->nonfinite_fraction, 2.0 / 16.0);
  EXPECT_EQ(e->rel_mse, 0.0);  // the rest matches
}

TEST(Metrics, SizeMismatchIsAnError) {
  EXPECT_EQ(CompareImages(Constant(4, 4, 1), Constant(4, 5, 1)).status().code(),
            absl::StatusCode::kInvalidArgument);
}

constexpr const char* kSpec = R"({
  "size": [32, 16], "reference": {"spp": 64}, "timed_frames": 2,
  "scenes": [{"name": "cornell_box",
              "views": [{"name": "side", "eye": [1, 0.3, 0.2], "target": [0.2, 0.2, 0.2], "yfov": 40}],
              "geometry_change": [{"node_transform": {"node": 6, "translation": {"x": 0.01}}},
                                  {"node_transform": {"node": 6}}],
              "light_change": [{"light": {"light": 0, "intensity": 2}},
                               {"light": {"light": 0, "intensity": 1}}]}],
  "solvers": [{"name": "direct", "grid": {"area_samples": ["16", 64], "shadow_res": ["128"]}}]
})";

TEST(EvalSpec, ParsesAGoodSpec) {
  auto spec = ParseEvalSpec(kSpec);
  ASSERT_TRUE(spec.ok()) << spec.status();
  EXPECT_EQ(spec->width, 32u);
  EXPECT_EQ(spec->height, 16u);
  EXPECT_EQ(spec->reference_spp, 64);
  ASSERT_EQ(spec->scenes.size(), 1u);
  ASSERT_EQ(spec->scenes[0].views.size(), 1u);
  EXPECT_TRUE(spec->scenes[0].views[0].look_at.has_value());
  EXPECT_EQ(spec->scenes[0].geometry_change[0].node_transform().node(), 6u);
  const auto settings = spec->solvers[0].Settings();
  ASSERT_EQ(settings.size(), 2u);  // 2 x 1
  EXPECT_EQ(settings[1].at("area_samples"), "64");
  EXPECT_EQ(settings[1].at("shadow_res"), "128");
  EXPECT_EQ(spec->refine_samples, 0u);  // the server's default
  std::string refined = kSpec;
  refined.replace(refined.find("\"timed_frames\""), 14, "\"refine_samples\": 4, \"timed_frames\"");
  spec = ParseEvalSpec(refined);
  ASSERT_TRUE(spec.ok()) << spec.status();
  EXPECT_EQ(spec->refine_samples, 4u);
  refined.replace(refined.find("\"refine_samples\": 4"), 19, "\"refine_samples\": 0");
  EXPECT_NE(std::string(ParseEvalSpec(refined).status().message()).find("refine_samples"),
            std::string::npos);
}

TEST(EvalSpec, ErrorsNameTheJsonPath) {
  std::string bad = kSpec;
  bad.replace(bad.find("\"size\": [32, 16]"), 16, "\"size\": [32, 0] ");
  auto spec = ParseEvalSpec(bad);
  ASSERT_FALSE(spec.ok());
  EXPECT_NE(std::string(spec.status().message()).find("size[1]"), std::string::npos)
      << spec.status();
  std::string pair = kSpec;
  pair.replace(pair.find("\"light_change\""), 14, "\"light_change\": [], \"x\"");
  spec = ParseEvalSpec(pair);
  ASSERT_FALSE(spec.ok());
  EXPECT_NE(std::string(spec.status().message()).find("scenes[0].light_change"), std::string::npos)
      << spec.status();
  EXPECT_FALSE(ParseEvalSpec("{\"scenes\": []}").ok());
  EXPECT_FALSE(ParseEvalSpec("{\"bogus\": 1}").ok());
}

// A scene's animation (issue 27): the script and its timing, defaults for
// what it leaves out; a bad value names its JSON path.
TEST(EvalSpec, ParsesASceneAnimation) {
  auto spec = ParseEvalSpec(kSpec);
  ASSERT_TRUE(spec.ok()) << spec.status();
  EXPECT_FALSE(spec->scenes[0].animation.has_value());
  std::string animated = kSpec;
  animated.replace(animated.find("\"light_change\""), 14,
                   "\"animation\": {\"script\": \"orbit.json\", \"duration_s\": 5, "
                   "\"fps\": 15}, \"light_change\"");
  spec = ParseEvalSpec(animated);
  ASSERT_TRUE(spec.ok()) << spec.status();
  ASSERT_TRUE(spec->scenes[0].animation.has_value());
  const EvalAnimation& a = *spec->scenes[0].animation;
  EXPECT_EQ(a.script, "orbit.json");
  EXPECT_EQ(a.duration_s, 5.0);
  EXPECT_EQ(a.fps, 15.0);
  EXPECT_EQ(a.warmup_s, 2.0);    // default
  EXPECT_EQ(a.update_hz, 10.0);  // default
  std::string bad = animated;
  bad.replace(bad.find("\"fps\": 15"), 9, "\"fps\": -1");
  auto refused = ParseEvalSpec(bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(std::string(refused.status().message()).find("scenes[0].animation.fps"),
            std::string::npos)
      << refused.status();
  bad = animated;
  bad.replace(bad.find("\"script\": \"orbit.json\""), 22, "\"script\": 3");
  refused = ParseEvalSpec(bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(std::string(refused.status().message()).find("scenes[0].animation.script"),
            std::string::npos)
      << refused.status();
}

TEST(EvalSpec, CacheKeyIsStableAndSensitive) {
  // FNV-1a 64 of "a" is a published test vector.
  EXPECT_EQ(Fnv1a("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(Fnv1a("cornell|64x64|256"), Fnv1a("cornell|64x64|256"));
  EXPECT_NE(Fnv1a("cornell|64x64|256"), Fnv1a("cornell|64x64|512"));
  EXPECT_NE(Fnv1a("cornell|64x64|256"), Fnv1a("cornell|64x32|256"));
}

TEST(Plot, DrawsTheSeriesWhereTheAxesPutThem) {
  const std::vector<PlotSeries> series = {{"a", {{1.0, 1.0}, {100.0, 0.01}}}};
  const Raster r = PlotLogLog(series, 320, 200);
  ASSERT_EQ(r.width, 320);
  ASSERT_EQ(r.rgba.size(), size_t(320 * 200 * 4));
  LogAxes axes;
  ASSERT_TRUE(ComputeAxes(series, 320, 200, axes));
  // The midpoint of the segment in log space, (10, 0.1), is on the line.
  const auto color = SeriesColor(0);
  EXPECT_EQ(r.at(axes.X(10.0), axes.Y(0.1)), color);
  EXPECT_EQ(r.at(axes.X(1.0), axes.Y(1.0)), color);  // a marker
  // A point far from the line stays background.
  // (Off the 2x and 5x grid lines too.)
  EXPECT_EQ(r.at(axes.X(3.0), axes.Y(0.03)), (std::array<uint8_t, 3>{255, 255, 255}));
}

TEST(Plot, LegendNamesEachSeriesAndThePngHasTheRequestedSize) {
  const std::vector<PlotSeries> series = {
      {"direct", {{20.0, 0.5}, {80.0, 0.2}}},
      {"pathtrace (equal time)", {{10.0, 1.0}, {1000.0, 0.002}}}};
  const Raster r = PlotLogLog(series, 400, 300);
  LogAxes axes;
  ASSERT_TRUE(ComputeAxes(series, 400, 300, axes));
  // Each legend row, under the plot: a swatch in the series colour and
  // black glyph pixels to its right.
  for (size_t i = 0; i < series.size(); ++i) {
    const int y = LegendRowY(axes, i);
    ASSERT_LT(y + 5, r.height);
    EXPECT_EQ(r.at(axes.left + 4, y), SeriesColor(i));
    int black = 0;
    for (int yy = y - 5; yy < y + 5; ++yy) {
      for (int x = axes.left + 16; x < axes.left + 16 + int(series[i].name.size()) * 8; ++x) {
        black += r.at(x, yy) == std::array<uint8_t, 3>{0, 0, 0};
      }
    }
    EXPECT_GT(black, 20) << series[i].name;
  }
  // Written as PNG, it decodes back at the requested size.
  auto png = EncodePng(r.rgba, r.width, r.height);
  ASSERT_TRUE(png.ok()) << png.status();
  auto decoded = DecodeImageBytes({reinterpret_cast<const uint8_t*>(png->data()), png->size()});
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_EQ(decoded->width, 400);
  EXPECT_EQ(decoded->height, 300);
}

TEST(Plot, NoUsablePointsGiveABlankCanvas) {
  const Raster r = PlotLogLog({{"a", {{0.0, 1.0}, {1.0, -1.0}}}}, 64, 48);
  ASSERT_EQ(r.rgba.size(), size_t(64 * 48 * 4));
  for (uint8_t v : r.rgba) ASSERT_EQ(v, 255);
}

}  // namespace eval_test
}  // namespace gistream::client
