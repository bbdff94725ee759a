#include "render/environment_lights.h"

#include <algorithm>
#include <cmath>
#include <queue>

namespace gistream {
namespace {

constexpr double kPi = 3.14159265358979323846;

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
  const double mid_theta = kPi * (0.5 * (r.y0 + r.y1)) / height;
  const double angular_w = w * (2.0 * kPi / width) * std::sin(mid_theta);
  const double angular_h = h * (kPi / height);
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

glm::dvec3 TexelDirection(int x, int y, int width, int height) {
  const double theta = kPi * (y + 0.5) / height, phi = 2.0 * kPi * (x + 0.5) / width;
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

}  // namespace

std::vector<EnvironmentRegionLight> MedianCutEnvironment(const Image& image, int count) {
  const int width = image.width, height = image.height;
  if (!image.is_float || width <= 0 || height <= 0 || count <= 0 ||
      image.pixelsf.size() < size_t(width) * size_t(height) * 4) {
    return {};
  }
  // Texel radiance, and energy = luminance x solid angle
  // (d(omega) = (2 pi / W)(pi / H) sin(theta)).
  const double texel_angle = (2.0 * kPi / width) * (kPi / height);
  std::vector<double> energy(size_t(width) * size_t(height), 0.0);
  auto radiance = [&](int x, int y) {
    const float* p = &image.pixelsf[(size_t(y) * size_t(width) + size_t(x)) * 4];
    const glm::dvec3 l(p[0], p[1], p[2]);
    return glm::all(glm::greaterThanEqual(l, glm::dvec3(0.0))) && std::isfinite(l.x + l.y + l.z)
               ? l
               : glm::dvec3(0.0);
  };
  for (int y = 0; y < height; ++y) {
    const double omega = texel_angle * std::sin(kPi * (y + 0.5) / height);
    for (int x = 0; x < width; ++x) {
      const glm::dvec3 l = radiance(x, y);
      energy[size_t(y) * size_t(width) + size_t(x)] =
          (0.2126 * l.x + 0.7152 * l.y + 0.0722 * l.z) * omega;
    }
  }
  const EnergyTable table(energy, width, height);
  std::priority_queue<Region> open;
  std::vector<Region> done;
  open.push({0, width, 0, height, table.Sum(0, width, 0, height)});
  if (!(open.top().energy > 0.0)) return {};
  // The region of most energy is cut first, until `count` regions.
  while (!open.empty() && int(open.size() + done.size()) < count) {
    const Region r = open.top();
    open.pop();
    Region a{}, b{};
    if (!Cut(r, table, width, height, a, b)) {
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
      const double omega = texel_angle * std::sin(kPi * (y + 0.5) / height);
      for (int x = r.x0; x < r.x1; ++x) {
        irradiance += radiance(x, y) * omega;
        centroid +=
            energy[size_t(y) * size_t(width) + size_t(x)] * TexelDirection(x, y, width, height);
      }
    }
    const double len = glm::length(centroid);
    if (!(r.energy > 0.0) || !(len > 0.0)) continue;
    lights.push_back({glm::vec3(centroid / len), glm::vec3(irradiance)});
  }
  return lights;
}

std::vector<EnvironmentRegionLight> PlaceEnvironmentLights(
    const std::vector<EnvironmentRegionLight>& cut, float rotation, float intensity) {
  // phi = atan2(x, -z) - rotation: a texel at phi is seen at phi + rotation.
  const float c = std::cos(rotation), s = std::sin(rotation);
  std::vector<EnvironmentRegionLight> out;
  out.reserve(cut.size());
  for (const EnvironmentRegionLight& l : cut) {
    const glm::vec3 d = l.to_sky;
    out.push_back({glm::vec3(d.x * c - d.z * s, d.y, d.x * s + d.z * c), l.irradiance * intensity});
  }
  return out;
}

std::vector<EnvironmentRegionLight> EnvironmentLights(const SceneState& state, int count) {
  const std::optional<Environment>& env = state.scene().environment;
  if (!env || count <= 0) return {};
  return PlaceEnvironmentLights(MedianCutEnvironment(env->image, count),
                                state.environment_rotation(), state.environment_intensity());
}

ChangeMask EnvironmentAsLights(ChangeMask changes, const SceneState& state) {
  if ((changes & kChangeEnvironment) && state.scene().environment) changes |= kChangeLights;
  return changes;
}

}  // namespace gistream
