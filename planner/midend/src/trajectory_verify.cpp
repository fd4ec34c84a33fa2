#include "trajectory_verify.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace porter::midend::detail {

std::string verify_trajectory(const Trajectory& traj, const std::vector<int>& piece_segment,
                              const MidendLimits& limits, double tolerance, double step_s) {
  const double total = traj.total_duration_s();
  const int steps = static_cast<int>(std::ceil(total / step_s));
  const double bound = 1.0 + tolerance;
  char buf[160];
  auto fail = [&](const char* what, double ratio, double t) {
    std::snprintf(buf, sizeof buf, "%s %.3g x limit at t = %.2f s", what, ratio, t);
    return std::string(buf);
  };
  Eigen::Vector2d last_v = Eigen::Vector2d::Zero();
  int last_segment = -1;
  constexpr double kMoving_mps = 1e-6;
  for (int k = 0; k <= steps; ++k) {
    const double t = std::min(k * step_s, total);
    const TrajectoryState st = traj.sample(t, limits.track_width_m, limits.wheel_radius_m);
    if (!st.z.allFinite() || !st.z_dot.allFinite() || !st.z_ddot.allFinite() ||
        !std::isfinite(st.wheels.left_radps) || !std::isfinite(st.wheels.right_radps) ||
        !std::isfinite(st.wheels.left_radps2) || !std::isfinite(st.wheels.right_radps2)) {
      std::snprintf(buf, sizeof buf, "non-finite state at t = %.2f s", t);
      return buf;
    }
    const double w = std::max(std::abs(st.wheels.left_radps), std::abs(st.wheels.right_radps)) /
                     limits.wheel_omega_max_radps;
    if (w > bound) return fail("wheel velocity", w, t);
    const double a = std::max(std::abs(st.wheels.left_radps2), std::abs(st.wheels.right_radps2)) /
                     limits.wheel_alpha_max_radps2;
    if (a > bound) return fail("wheel acceleration", a, t);
    for (int j = 0; j < kNumArmJoints; ++j) {
      const double qd = std::abs(st.z_dot[2 + j]) / limits.joint_velocity_max_radps[j];
      if (qd > bound) return fail("joint velocity", qd, t);
      const double qdd = std::abs(st.z_ddot[2 + j]) / limits.joint_acceleration_max_radps2[j];
      if (qdd > bound) return fail("joint acceleration", qdd, t);
      const double range = limits.joint_upper_rad[j] - limits.joint_lower_rad[j];
      const double q = st.z[2 + j];
      if (q > limits.joint_upper_rad[j] + tolerance * range || q < limits.joint_lower_rad[j] - tolerance * range) {
        std::snprintf(buf, sizeof buf, "joint %d position %.3f rad outside its bounds at t = %.2f s", j + 1, q, t);
        return buf;
      }
    }
    const std::size_t p = static_cast<std::size_t>(st.piece);
    const int segment = p < piece_segment.size() ? piece_segment[p] : 0;
    if (segment != last_segment) {
      last_segment = segment;
      last_v.setZero();
    }
    const Eigen::Vector2d v = st.z_dot.head<2>();
    if (v.norm() > kMoving_mps) {
      if (last_v.norm() > kMoving_mps && v.dot(last_v) < 0.0) {
        std::snprintf(buf, sizeof buf, "the base reverses inside a segment at t = %.2f s", t);
        return buf;
      }
      last_v = v;
    }
  }
  return {};
}

}  // namespace porter::midend::detail
