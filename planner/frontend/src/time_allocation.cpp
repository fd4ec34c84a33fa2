#include "porter/frontend/time_allocation.hpp"
#include "porter/planner/angle.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace porter::frontend {

bool validate_settings(const TimeAllocationSettings& s, std::string* why) {
  auto bad = [&](const char* field) {
    if (why) *why = std::string("TimeAllocationSettings.") + field + " out of range";
    return false;
  };
  if (!(s.base_speed_fraction > 0.0 && s.base_speed_fraction <= 1.0)) return bad("base_speed_fraction");
  if (!(s.base_accel_fraction > 0.0 && s.base_accel_fraction <= 1.0)) return bad("base_accel_fraction");
  if (!(s.joint_speed_fraction > 0.0 && s.joint_speed_fraction <= 1.0)) return bad("joint_speed_fraction");
  if (!(s.min_step_time_s > 0.0)) return bad("min_step_time_s");
  return true;
}

void step_arc(const BasePose& a, const BasePose& b, double* length_m, double* curvature_1pm) {
  const double chord = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m);
  const double dyaw = std::abs(planner::wrap_angle_rad(b.yaw_rad - a.yaw_rad));
  const double half = 0.5 * dyaw;
  const double len = half < 1e-6 ? chord : chord * half / std::sin(half);
  *length_m = len;
  *curvature_1pm = len > 1e-9 ? dyaw / len : 0.0;
}

namespace {

/// Time to cover `s` starting at v0 and ending at v1 with acceleration a and speed cap vmax
/// (v0, v1 <= vmax and reachable from each other within s).
double trapezoid_time(double s, double v0, double v1, double a, double vmax) {
  if (s <= 1e-12) return 0.0;
  const double vp = std::min(vmax, std::sqrt(std::max(0.0, (2.0 * a * s + v0 * v0 + v1 * v1) / 2.0)));
  if (vp <= 1e-12) return 0.0;
  const double s_acc = (vp * vp - v0 * v0) / (2.0 * a), s_dec = (vp * vp - v1 * v1) / (2.0 * a);
  const double cruise = std::max(0.0, s - s_acc - s_dec);
  return std::max(0.0, vp - v0) / a + std::max(0.0, vp - v1) / a + cruise / vp;
}

std::vector<double> base_profile(const RobotModel& model, const std::vector<BasePose>& poses,
                                 const std::vector<int>& etas, const TimeAllocationSettings& st) {
  const std::size_t n = poses.size();
  std::vector<double> times(n > 0 ? n - 1 : 0, 0.0);
  if (n < 2) return times;
  const double r = model.base.wheel_radius_m, d = model.base.track_width_m;
  std::vector<double> len(n - 1), vcap(n - 1), acc(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    double kappa = 0.0;
    step_arc(poses[i], poses[i + 1], &len[i], &kappa);
    const double scale = 1.0 + kappa * d / 2.0;
    vcap[i] = st.base_speed_fraction * model.base.wheel_omega_max_radps * r / scale;
    acc[i] = st.base_accel_fraction * model.base.wheel_alpha_max_radps2 * r / scale;
  }
  // Node speeds: zero at the ends and at gear switches; capped by the adjacent steps.
  std::vector<double> v(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const bool gear_switch = etas[i + 1] != etas[i];
    v[i] = gear_switch ? 0.0 : std::min(vcap[i - 1], vcap[i]);
  }
  for (std::size_t i = 0; i + 1 < n; ++i) v[i + 1] = std::min(v[i + 1], std::sqrt(v[i] * v[i] + 2.0 * acc[i] * len[i]));
  for (std::size_t i = n - 1; i > 0; --i) v[i - 1] = std::min(v[i - 1], std::sqrt(v[i] * v[i] + 2.0 * acc[i - 1] * len[i - 1]));
  for (std::size_t i = 0; i + 1 < n; ++i) times[i] = trapezoid_time(len[i], v[i], v[i + 1], acc[i], vcap[i]);
  return times;
}

}  // namespace

std::vector<double> base_step_times(const RobotModel& model, const std::vector<BaseSample>& samples,
                                    const TimeAllocationSettings& st) {
  std::vector<BasePose> poses;
  std::vector<int> etas;
  for (const auto& s : samples) poses.push_back(s.pose), etas.push_back(s.eta);
  std::vector<double> t = base_profile(model, poses, etas, st);
  for (double& x : t) x = std::max(x, st.min_step_time_s);
  return t;
}

std::vector<double> whole_body_step_times(const RobotModel& model, const std::vector<WholeBodySample>& samples,
                                          const TimeAllocationSettings& st) {
  std::vector<BasePose> poses;
  std::vector<int> etas;
  for (const auto& s : samples) poses.push_back(s.config.base), etas.push_back(s.eta);
  std::vector<double> t = base_profile(model, poses, etas, st);
  const JointVector vmax = st.joint_speed_fraction * model.velocity_limits();
  for (std::size_t i = 0; i < t.size(); ++i) {
    const JointVector dq = (samples[i + 1].config.q_rad - samples[i].config.q_rad).cwiseAbs();
    t[i] = std::max({t[i], (dq.array() / vmax.array()).maxCoeff(), st.min_step_time_s});
  }
  return t;
}

}  // namespace porter::frontend
