#include "porter/state/pose2.hpp"

#include <cmath>

namespace porter::state {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

double wrap_angle(double angle_rad) {
  if (!std::isfinite(angle_rad)) return angle_rad;
  double a = std::remainder(angle_rad, 2.0 * kPi);
  if (a <= -kPi) a += 2.0 * kPi;
  return a;
}

BasePose compose(const BasePose& T_A_B, const BasePose& T_B_C) {
  const double c = std::cos(T_A_B.yaw_rad);
  const double s = std::sin(T_A_B.yaw_rad);
  return {T_A_B.x_m + c * T_B_C.x_m - s * T_B_C.y_m, T_A_B.y_m + s * T_B_C.x_m + c * T_B_C.y_m,
          wrap_angle(T_A_B.yaw_rad + T_B_C.yaw_rad)};
}

BasePose inverse(const BasePose& T_A_B) {
  const double c = std::cos(T_A_B.yaw_rad);
  const double s = std::sin(T_A_B.yaw_rad);
  return {-(c * T_A_B.x_m + s * T_A_B.y_m), -(-s * T_A_B.x_m + c * T_A_B.y_m),
          wrap_angle(-T_A_B.yaw_rad)};
}

BasePose between(const BasePose& T_A_B, const BasePose& T_A_C) {
  return compose(inverse(T_A_B), T_A_C);
}

BasePose interpolate(const BasePose& a, const BasePose& b, double s) {
  return {a.x_m + s * (b.x_m - a.x_m), a.y_m + s * (b.y_m - a.y_m),
          wrap_angle(a.yaw_rad + s * wrap_angle(b.yaw_rad - a.yaw_rad))};
}

BasePose integrate_unicycle(const BasePose& start, double v_mps, double omega_radps, double dt_s) {
  const double dyaw = omega_radps * dt_s;
  double fx, fy;  // displacement in the start frame
  if (std::abs(dyaw) < 1e-9) {
    fx = v_mps * dt_s * std::cos(0.5 * dyaw);
    fy = v_mps * dt_s * std::sin(0.5 * dyaw);
  } else {
    const double r = v_mps / omega_radps;
    fx = r * std::sin(dyaw);
    fy = r * (1.0 - std::cos(dyaw));
  }
  return compose(start, BasePose{fx, fy, dyaw});
}

}  // namespace porter::state
