// A log-log line plot rendered into an RGBA8 raster (no plotting library in
// Debian's C++ world that we want to depend on): one polyline with markers
// per series, decade grid lines with exponent labels, a colour legend.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace gistream::client {

struct PlotSeries {
  std::string name;
  std::vector<std::pair<double, double>> points;  // (x, y), both > 0
};

struct Raster {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // rows top first
  std::array<uint8_t, 3> at(int x, int y) const {
    const uint8_t* p = &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4];
    return {p[0], p[1], p[2]};
  }
};

// The colour series i is drawn in (also used by the markdown legend).
std::array<uint8_t, 3> SeriesColor(size_t i);
const char* SeriesColorName(size_t i);

// Points that are not finite and > 0 are skipped.
Raster PlotLogLog(const std::vector<PlotSeries>& series, int width, int height);

// Maps a value to a pixel column/row of the plot area, as PlotLogLog does
// (exposed for tests). Returns false when the series have no usable point.
struct LogAxes {
  double x0, x1, y0, y1;  // decades (log10) spanned
  int left, right, top, bottom;
  int X(double x) const;
  int Y(double y) const;
};
bool ComputeAxes(const std::vector<PlotSeries>& series, int width, int height, LogAxes& axes);

// The centre row of series i's legend entry (below the plot area): a swatch
// at x = left + 4, the name from x = left + 16.
int LegendRowY(const LogAxes& axes, size_t i);

}  // namespace gistream::client
