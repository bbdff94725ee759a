// Line plots rendered into an RGBA8 raster (no plotting library in Debian's
// C++ world that we want to depend on): one polyline with markers per
// series, grid lines with labels (decades on a log axis, 1-2-5 steps on a
// linear one), axis titles and a colour legend.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace gistream::client {

struct PlotSeries {
  std::string name;
  std::vector<std::pair<double, double>> points;  // (x, y); > 0 on a log axis
};

enum class AxisScale { kLog, kLinear };

struct PlotStyle {
  std::string x_title = "full update ms";
  std::string y_title = "relMSE";
  AxisScale x_scale = AxisScale::kLog;
  AxisScale y_scale = AxisScale::kLog;
  bool markers = true;  // a box at every point (off for dense curves like CDFs)
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

// Points that are not finite (or not > 0 on a log axis) are skipped.
Raster PlotLines(const std::vector<PlotSeries>& series, const PlotStyle& style, int width,
                 int height);
// eval's plot: relMSE against full update ms, both log.
Raster PlotLogLog(const std::vector<PlotSeries>& series, int width, int height);

// Maps a value to a pixel column/row of the plot area, as PlotLines does
// (exposed for tests). Returns false when the series have no usable point.
struct LogAxes {
  // Decades (log10) spanned on a log axis; the value range on a linear one.
  double x0, x1, y0, y1;
  int left, right, top, bottom;
  bool x_log = true, y_log = true;
  double x_step = 1.0, y_step = 1.0;  // grid spacing in the units above
  int X(double x) const;
  int Y(double y) const;
};
bool ComputeAxes(const std::vector<PlotSeries>& series, int width, int height, LogAxes& axes);
bool ComputeAxes(const std::vector<PlotSeries>& series, const PlotStyle& style, int width,
                 int height, LogAxes& axes);

// The centre row of series i's legend entry (below the plot area): a swatch
// at x = left + 4, the name from x = left + 16.
int LegendRowY(const LogAxes& axes, size_t i);

}  // namespace gistream::client
