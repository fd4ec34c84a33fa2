#pragma once
// The one angle-wrapping helper of the planner stages. Header-only, pure.

#include <cmath>

namespace porter::planner {

/// a wrapped to (-pi, pi] (exact: std::remainder, then -pi moved to pi). NaN stays NaN.
inline double wrap_angle_rad(double a_rad) {
  constexpr double kPi = 3.14159265358979323846;
  double r = std::remainder(a_rad, 2.0 * kPi);
  if (r <= -kPi) r += 2.0 * kPi;
  return r;
}

/// The shortest signed rotation from b to a, a - b wrapped to (-pi, pi].
inline double angle_difference_rad(double a_rad, double b_rad) { return wrap_angle_rad(a_rad - b_rad); }

}  // namespace porter::planner
