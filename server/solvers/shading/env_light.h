// The environment map as a distant light for the reference path tracer:
// radiance lookup and importance sampling in proportion to luminance x
// sin(theta) (a piecewise-constant 2D distribution over the texels, as in
// PBRT's ImageInfiniteLight), with the solid-angle pdf that MIS needs.
//
// Convention (the path tracer's; render/environment_lights.h cuts the map
// into lights for the rasterizing solvers in the same one): equirectangular, +Y up, theta = acos(y)
// from the top row, and phi = atan2(x, -z) - rotation, so u = 0 looks along -Z and the rotation
// (radians about +Y) turns the map. Texels are looked up nearest, matching
// the piecewise-constant pdf exactly.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace gistream::shading {

class EnvironmentLight {
 public:
  // `image`: linear float RGBA, width x height >= 1 (else the light is off).
  explicit EnvironmentLight(const Image& image);

  bool empty() const { return total_ <= 0.0; }
  // Radiance towards -dir (dir points away from the scene), before
  // intensity; `rotation` in radians about +Y.
  glm::vec3 Radiance(const glm::vec3& dir, float rotation) const;
  // Solid-angle pdf of Sample returning `dir`.
  float Pdf(const glm::vec3& dir, float rotation) const;
  // A direction drawn from the distribution (u1 picks the row, u2 the
  // column; their remainders place the point in the texel); pdf (solid
  // angle) out, 0 when the sample is unusable (a pole, a black map).
  glm::vec3 Sample(float u1, float u2, float rotation, float& pdf) const;

 private:
  // Texel (x, y) and texel-space coordinates of a direction.
  void Locate(const glm::vec3& dir, float rotation, int& x, int& y, float& sin_theta) const;

  const Image& image_;
  int width_ = 0, height_ = 0;
  std::vector<double> row_cdf_;   // height + 1 entries
  std::vector<double> cell_cdf_;  // height x (width + 1) entries, per row
  std::vector<float> weight_;     // width x height texel weights
  double total_ = 0.0;
};

}  // namespace gistream::shading
