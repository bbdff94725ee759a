// Closed-form configuration factors for the analytic light tests.
#pragma once

#include <cmath>

namespace gistream::testing {

// From a differential area to a parallel a x b rectangle at height h whose
// corner lies straight above (or below) it (Howell's catalogue C-11):
//   F = 1/(2 pi) [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2))
//                 + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2))],  X = a/h, Y = b/h.
// A rectangle elsewhere in the parallel plane is a sum and difference of
// such corner rectangles. The irradiance from a Lambertian emitter of
// radiance L is pi L F.
inline double CornerFormFactor(double a, double b, double h) {
  constexpr double kPi = 3.14159265358979;
  const double x = a / h, y = b / h;
  return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
          y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
         (2.0 * kPi);
}

}  // namespace gistream::testing
