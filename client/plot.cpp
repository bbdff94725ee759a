#include "plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace gistream::client {
namespace {

constexpr std::array<std::array<uint8_t, 3>, 8> kPalette = {{{31, 119, 180},
                                                             {214, 39, 40},
                                                             {44, 160, 44},
                                                             {255, 127, 14},
                                                             {148, 103, 189},
                                                             {140, 86, 75},
                                                             {227, 119, 194},
                                                             {127, 127, 127}}};
constexpr const char* kPaletteNames[] = {"blue",   "red",   "green", "orange",
                                         "purple", "brown", "pink",  "grey"};

// 3x5 glyphs for tick labels and the legend: digits, letters (drawn upper
// case) and a few symbols (one row per byte, 3 bits, the high bit left).
uint8_t GlyphRow(char c, int row) {
  static const uint8_t kDigits[10][5] = {
      {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
      {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};
  static const uint8_t kLetters[26][5] = {
      {2, 5, 7, 5, 5}, {6, 5, 6, 5, 6}, {3, 4, 4, 4, 3}, {6, 5, 5, 5, 6}, {7, 4, 6, 4, 7},
      {7, 4, 6, 4, 4}, {3, 4, 5, 5, 3}, {5, 5, 7, 5, 5}, {7, 2, 2, 2, 7}, {1, 1, 1, 5, 2},
      {5, 5, 6, 5, 5}, {4, 4, 4, 4, 7}, {5, 7, 7, 5, 5}, {6, 5, 5, 5, 5}, {2, 5, 5, 5, 2},
      {6, 5, 6, 4, 4}, {2, 5, 5, 6, 3}, {6, 5, 6, 5, 5}, {3, 4, 2, 1, 6}, {7, 2, 2, 2, 2},
      {5, 5, 5, 5, 7}, {5, 5, 5, 5, 2}, {5, 5, 7, 7, 5}, {5, 5, 2, 5, 5}, {5, 5, 2, 2, 2},
      {7, 1, 2, 4, 7}};
  if (c >= '0' && c <= '9') return kDigits[c - '0'][row];
  if (c >= 'a' && c <= 'z') c = char(c - 'a' + 'A');
  if (c >= 'A' && c <= 'Z') return kLetters[c - 'A'][row];
  static const uint8_t kSlash[5] = {1, 1, 2, 4, 4}, kColon[5] = {0, 2, 0, 2, 0},
                       kOpen[5] = {1, 2, 2, 2, 1}, kClose[5] = {4, 2, 2, 2, 4},
                       kEquals[5] = {0, 7, 0, 7, 0};
  switch (c) {
    case '-': return row == 2 ? 7 : 0;
    case '_': return row == 4 ? 7 : 0;
    case '.': return row == 4 ? 2 : 0;
    case '/': return kSlash[row];
    case ':': return kColon[row];
    case '(': return kOpen[row];
    case ')': return kClose[row];
    case '=': return kEquals[row];
    default: return 0;
  }
}

constexpr int kGlyphAdvance = 8;  // 3x5 glyph bits as 2x2 blocks, 2 px apart
constexpr int kLegendRow = 14;

void Put(Raster& r, int x, int y, std::array<uint8_t, 3> c) {
  if (x < 0 || y < 0 || x >= r.width || y >= r.height) return;
  uint8_t* p = &r.rgba[(size_t(y) * size_t(r.width) + size_t(x)) * 4];
  p[0] = c[0];
  p[1] = c[1];
  p[2] = c[2];
  p[3] = 255;
}

void Line(Raster& r, int x0, int y0, int x1, int y1, std::array<uint8_t, 3> c, int thickness) {
  const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  for (;;) {
    for (int ty = 0; ty < thickness; ++ty) {
      for (int tx = 0; tx < thickness; ++tx)
        Put(r, x0 + tx - thickness / 2, y0 + ty - thickness / 2, c);
    }
    if (x0 == x1 && y0 == y1) break;
    const int e2 = 2 * err;
    if (e2 >= dy) err += dy, x0 += sx;
    if (e2 <= dx) err += dx, y0 += sy;
  }
}

void Box(Raster& r, int x, int y, int half, std::array<uint8_t, 3> c) {
  for (int dy = -half; dy <= half; ++dy) {
    for (int dx = -half; dx <= half; ++dx) Put(r, x + dx, y + dy, c);
  }
}

// Each glyph bit is a scale x scale block; returns the x after the text.
int Text(Raster& r, int x, int y, const std::string& s, std::array<uint8_t, 3> c, int scale = 2) {
  for (char ch : s) {
    for (int row = 0; row < 5; ++row) {
      const uint8_t bits = GlyphRow(ch, row);
      for (int col = 0; col < 3; ++col) {
        if (!(bits & (4 >> col))) continue;
        for (int sy = 0; sy < scale; ++sy) {
          for (int sx = 0; sx < scale; ++sx) {
            Put(r, x + col * scale + sx, y + row * scale + sy, c);
          }
        }
      }
    }
    x += kGlyphAdvance * scale / 2;
  }
  return x;
}

// "10" with the exponent k raised and smaller; returns the x after it.
int DecadeLabel(Raster& r, int x, int y, int k, std::array<uint8_t, 3> c) {
  x = Text(r, x, y, "10", c);
  return Text(r, x, y - 4, std::to_string(k), c, 1);
}
int DecadeLabelWidth(int k) {
  return 2 * kGlyphAdvance + int(std::to_string(k).size()) * kGlyphAdvance / 2;
}

bool Usable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }

// A 1, 2 or 5 times a power of ten step giving about `ticks` intervals.
double NiceStep(double span, int ticks) {
  const double raw = span / std::max(ticks, 1);
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * decade >= raw) return m * decade;
  }
  return 10.0 * decade;
}

// Axis range [lo, hi] of the usable values, as decades or padded values.
void AxisRange(double lo, double hi, bool log, double& a0, double& a1, double& step) {
  if (log) {
    a0 = std::floor(std::log10(lo));
    a1 = std::max(std::ceil(std::log10(hi)), a0 + 1);
    step = 1.0;
    return;
  }
  // Linear axes start at 0 for non-negative data (rates, fractions).
  if (lo >= 0.0) lo = 0.0;
  if (hi <= lo) hi = lo + 1.0;
  step = NiceStep(hi - lo, 5);
  a0 = std::floor(lo / step) * step;
  a1 = std::ceil(hi / step) * step;
}

std::string TickLabel(double v, double step) {
  char buf[32];
  if (std::fabs(v) < step * 1e-6) v = 0.0;
  const int decimals = step >= 1.0 ? 0 : int(std::ceil(-std::log10(step)));
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace

std::array<uint8_t, 3> SeriesColor(size_t i) { return kPalette[i % kPalette.size()]; }
const char* SeriesColorName(size_t i) { return kPaletteNames[i % kPalette.size()]; }

int LegendRowY(const LogAxes& axes, size_t i) { return axes.bottom + 48 + int(i) * kLegendRow; }

int LogAxes::X(double x) const {
  const double u = x_log ? std::log10(x) : x;
  return left + int(std::lround((u - x0) / (x1 - x0) * double(right - left)));
}
int LogAxes::Y(double y) const {
  const double u = y_log ? std::log10(y) : y;
  return bottom - int(std::lround((u - y0) / (y1 - y0) * double(bottom - top)));
}

bool ComputeAxes(const std::vector<PlotSeries>& series, int width, int height, LogAxes& axes) {
  return ComputeAxes(series, PlotStyle{}, width, height, axes);
}

bool ComputeAxes(const std::vector<PlotSeries>& series, const PlotStyle& style, int width,
                 int height, LogAxes& axes) {
  axes.x_log = style.x_scale == AxisScale::kLog;
  axes.y_log = style.y_scale == AxisScale::kLog;
  double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
  for (const PlotSeries& s : series) {
    for (const auto& [x, y] : s.points) {
      if (!Usable(x, axes.x_log) || !Usable(y, axes.y_log)) continue;
      x_lo = std::min(x_lo, x);
      x_hi = std::max(x_hi, x);
      y_lo = std::min(y_lo, y);
      y_hi = std::max(y_hi, y);
    }
  }
  if (x_lo > x_hi) return false;
  AxisRange(x_lo, x_hi, axes.x_log, axes.x0, axes.x1, axes.x_step);
  AxisRange(y_lo, y_hi, axes.y_log, axes.y0, axes.y1, axes.y_step);
  axes.left = 60;
  axes.right = width - 20;
  axes.top = 24;
  // Below the x axis: tick labels, the axis title, then a legend row per
  // series (the legend never hides data).
  axes.bottom = height - 48 - kLegendRow * int(series.size());
  return axes.right > axes.left && axes.bottom > axes.top;
}

namespace {

// Grid and labels: 10^k on a log axis, the value on a linear one; a log
// axis of at most two decades also gets 2 and 5 times each decade.
void DrawGrid(Raster& r, const LogAxes& axes) {
  const std::array<uint8_t, 3> grid{225, 225, 225}, black{0, 0, 0};
  // Grid and labels: 10^k on a log axis, the value on a linear one.
  for (double k = axes.x0; k <= axes.x1 + axes.x_step * 1e-9; k += axes.x_step) {
    const int x = axes.X(axes.x_log ? std::pow(10.0, k) : k);
    Line(r, x, axes.top, x, axes.bottom, grid, 1);
    if (axes.x_log) {
      DecadeLabel(r, x - DecadeLabelWidth(int(k)) / 2, axes.bottom + 8, int(k), black);
    } else {
      const std::string label = TickLabel(k, axes.x_step);
      Text(r, x - int(label.size()) * kGlyphAdvance / 2, axes.bottom + 8, label, black);
    }
  }
  // A log axis of at most two decades also gets 2 and 5 times each decade,
  // labelled plainly (session counts, latencies in ms read better so).
  auto minor = [](double d0, double d1) {
    std::vector<double> values;
    if (d1 - d0 > 2.0) return values;
    for (double k = d0; k < d1; k += 1) {
      for (double m : {2.0, 5.0}) values.push_back(m * std::pow(10.0, k));
    }
    return values;
  };
  if (axes.x_log) {
    for (double v : minor(axes.x0, axes.x1)) {
      const int x = axes.X(v);
      Line(r, x, axes.top, x, axes.bottom, grid, 1);
      const std::string label = TickLabel(v, v >= 1.0 ? 1.0 : v);
      Text(r, x - int(label.size()) * kGlyphAdvance / 2, axes.bottom + 8, label, black);
    }
  }
  if (axes.y_log) {
    for (double v : minor(axes.y0, axes.y1)) {
      const int y = axes.Y(v);
      Line(r, axes.left, y, axes.right, y, grid, 1);
      const std::string label = TickLabel(v, v >= 1.0 ? 1.0 : v);
      Text(r, axes.left - 6 - int(label.size()) * kGlyphAdvance, y - 5, label, black);
    }
  }
  for (double k = axes.y0; k <= axes.y1 + axes.y_step * 1e-9; k += axes.y_step) {
    const int y = axes.Y(axes.y_log ? std::pow(10.0, k) : k);
    Line(r, axes.left, y, axes.right, y, grid, 1);
    if (axes.y_log) {
      DecadeLabel(r, axes.left - 6 - DecadeLabelWidth(int(k)), y - 5, int(k), black);
    } else {
      const std::string label = TickLabel(k, axes.y_step);
      Text(r, axes.left - 6 - int(label.size()) * kGlyphAdvance, y - 5, label, black);
    }
  }
}

// Each series' polyline (points a log axis cannot show left out), with
// markers when asked.
void DrawSeries(Raster& r, const LogAxes& axes, const std::vector<PlotSeries>& series,
                bool markers) {
  for (size_t i = 0; i < series.size(); ++i) {
    const auto color = SeriesColor(i);
    std::vector<std::pair<double, double>> pts;
    for (const auto& p : series[i].points) {
      if (Usable(p.first, axes.x_log) && Usable(p.second, axes.y_log)) pts.push_back(p);
    }
    std::sort(pts.begin(), pts.end());
    for (size_t k = 0; k + 1 < pts.size(); ++k) {
      Line(r, axes.X(pts[k].first), axes.Y(pts[k].second), axes.X(pts[k + 1].first),
           axes.Y(pts[k + 1].second), color, 2);
    }
    if (markers) {
      for (const auto& p : pts) Box(r, axes.X(p.first), axes.Y(p.second), 3, color);
    }
  }
}

}  // namespace

Raster PlotLogLog(const std::vector<PlotSeries>& series, int width, int height) {
  return PlotLines(series, PlotStyle{}, width, height);
}

Raster PlotLines(const std::vector<PlotSeries>& series, const PlotStyle& style, int width,
                 int height) {
  Raster r;
  r.width = width;
  r.height = height;
  r.rgba.assign(size_t(width) * size_t(height) * 4, 255);
  LogAxes axes;
  if (!ComputeAxes(series, style, width, height, axes)) return r;
  const std::array<uint8_t, 3> black{0, 0, 0};
  DrawGrid(r, axes);
  Text(r, axes.right - int(style.x_title.size() + 1) * kGlyphAdvance, axes.bottom + 24,
       style.x_title, black);
  Text(r, 4, 4, style.y_title, black);
  Line(r, axes.left, axes.bottom, axes.right, axes.bottom, black, 1);
  Line(r, axes.left, axes.top, axes.left, axes.bottom, black, 1);
  DrawSeries(r, axes, series, style.markers);
  // Legend under the plot: a swatch and the name per series.
  for (size_t i = 0; i < series.size(); ++i) {
    const int y = LegendRowY(axes, i);
    Box(r, axes.left + 4, y, 4, SeriesColor(i));
    Text(r, axes.left + 16, y - 5, series[i].name, black);
  }
  return r;
}

}  // namespace gistream::client
