#include "scene/environment_cut.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <numbers>

namespace gistream {
namespace {

struct Region {
  int x0, x1, y0, y1;  // texels [x0, x1) x [y0, y1)
  double energy;
  bool operator<(const Region& o) const { return energy < o.energy; }  // max-heap
};

// Summed-area table of the texels' energy, (width + 1) x (height + 1).
class EnergyTable {
 public:
  EnergyTable(const std::vector<double>& energy, int width, int height)
      : width_(width), sum_(size_t(width + 1) * size_t(height + 1), 0.0) {
    for (int y = 0; y < height; ++y) {
      double row = 0.0;
      for (int x = 0; x < width; ++x) {
        row += energy[size_t(y) * size_t(width) + size_t(x)];
        At(x + 1, y + 1) = At(x + 1, y) + row;
      }
    }
  }
  double Sum(int x0, int x1, int y0, int y1) const {
    return At(x1, y1) - At(x0, y1) - At(x1, y0) + At(x0, y0);
  }

 private:
  double& At(int x, int y) { return sum_[size_t(y) * size_t(width_ + 1) + size_t(x)]; }
  double At(int x, int y) const { return sum_[size_t(y) * size_t(width_ + 1) + size_t(x)]; }
  int width_;
  std::vector<double> sum_;
};

// Where to cut `r` across its longer side (in angle), at the energy's
// median; false when it is one texel.
bool Cut(const Region& r, const EnergyTable& table, int width, int height, Region& a, Region& b) {
  const int w = r.x1 - r.x0, h = r.y1 - r.y0;
  if (w <= 1 && h <= 1) return false;
  const double mid_theta = std::numbers::pi * (0.5 * (r.y0 + r.y1)) / height;
  const double angular_w = w * (2.0 * std::numbers::pi / width) * std::sin(mid_theta);
  const double angular_h = h * (std::numbers::pi / height);
  const bool across_x = h <= 1 || (w > 1 && angular_w >= angular_h);
  a = b = r;
  const double half = 0.5 * r.energy;
  if (across_x) {
    int cut = r.x0 + 1;
    while (cut < r.x1 - 1 && table.Sum(r.x0, cut, r.y0, r.y1) < half) ++cut;
    a.x1 = b.x0 = cut;
  } else {
    int cut = r.y0 + 1;
    while (cut < r.y1 - 1 && table.Sum(r.x0, r.x1, r.y0, cut) < half) ++cut;
    a.y1 = b.y0 = cut;
  }
  a.energy = table.Sum(a.x0, a.x1, a.y0, a.y1);
  b.energy = table.Sum(b.x0, b.x1, b.y0, b.y1);
  return true;
}

// The map summed into cells of sx x sy texels: per cell its energy
// (luminance x solid angle), irradiance sum L d(omega) and energy-weighted
// direction.
struct Cells {
  int width = 0, height = 0;
  std::vector<double> energy;
  std::vector<glm::dvec3> irradiance, centroid;
};

Cells SumIntoCells(const Image& image, int sx, int sy) {
  const int w = image.width, h = image.height;
  Cells c;
  c.width = (w + sx - 1) / sx;
  c.height = (h + sy - 1) / sy;
  const size_t n = size_t(c.width) * size_t(c.height);
  c.energy.assign(n, 0.0);
  c.irradiance.assign(n, glm::dvec3(0.0));
  c.centroid.assign(n, glm::dvec3(0.0));
  // d(omega) = (2 pi / W)(pi / H) sin(theta) per texel.
  const double texel_angle = (2.0 * std::numbers::pi / w) * (std::numbers::pi / h);
  for (int y = 0; y < h; ++y) {
    const double theta = std::numbers::pi * (y + 0.5) / h;
    const double omega = texel_angle * std::sin(theta);
    for (int x = 0; x < w; ++x) {
      const float* p = &image.pixelsf[(size_t(y) * size_t(w) + size_t(x)) * 4];
      glm::dvec3 l(p[0], p[1], p[2]);
      // Negative or non-finite texels carry no light.
      if (!(l.x >= 0.0 && l.y >= 0.0 && l.z >= 0.0) || !std::isfinite(l.x + l.y + l.z)) {
        l = glm::dvec3(0.0);
      }
      const double e = (0.2126 * l.x + 0.7152 * l.y + 0.0722 * l.z) * omega;
      const double phi = 2.0 * std::numbers::pi * (x + 0.5) / w;
      const glm::dvec3 dir(std::sin(theta) * std::sin(phi), std::cos(theta),
                           -std::sin(theta) * std::cos(phi));
      const size_t cell = size_t(y / sy) * size_t(c.width) + size_t(x / sx);
      c.energy[cell] += e;
      c.irradiance[cell] += l * omega;
      c.centroid[cell] += e * dir;
    }
  }
  return c;
}

}  // namespace

std::vector<EnvironmentRegionLight> MedianCutEnvironment(const Image& image, int count) {
  const int width = image.width, height = image.height;
  if (!image.is_float || width <= 0 || height <= 0 || count <= 0 ||
      image.pixelsf.size() < size_t(width) * size_t(height) * 4) {
    return {};
  }
  constexpr int kMaxCellsX = 512, kMaxCellsY = 256;
  const Cells cells = SumIntoCells(image, (width + kMaxCellsX - 1) / kMaxCellsX,
                                   (height + kMaxCellsY - 1) / kMaxCellsY);
  const EnergyTable table(cells.energy, cells.width, cells.height);
  std::priority_queue<Region> open;
  std::vector<Region> done;
  open.push({0, cells.width, 0, cells.height, table.Sum(0, cells.width, 0, cells.height)});
  if (!(open.top().energy > 0.0)) return {};
  // The region of most energy is cut first, until `count` regions.
  while (!open.empty() && int(open.size() + done.size()) < count) {
    const Region r = open.top();
    open.pop();
    Region a{}, b{};
    if (!Cut(r, table, cells.width, cells.height, a, b)) {
      done.push_back(r);
      continue;
    }
    open.push(a);
    open.push(b);
  }
  while (!open.empty()) {
    done.push_back(open.top());
    open.pop();
  }
  std::vector<EnvironmentRegionLight> lights;
  for (const Region& r : done) {
    glm::dvec3 irradiance(0.0), centroid(0.0);
    for (int y = r.y0; y < r.y1; ++y) {
      for (int x = r.x0; x < r.x1; ++x) {
        const size_t cell = size_t(y) * size_t(cells.width) + size_t(x);
        irradiance += cells.irradiance[cell];
        centroid += cells.centroid[cell];
      }
    }
    const double len = glm::length(centroid);
    if (!(r.energy > 0.0) || !(len > 0.0)) continue;
    lights.push_back({glm::vec3(centroid / len), glm::vec3(irradiance)});
  }
  return lights;
}

}  // namespace gistream
