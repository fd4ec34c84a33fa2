#include "porter/tracker/control_law.hpp"

#include <algorithm>
#include <cmath>

namespace porter::tracker {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double wrap_angle(double angle_rad) {
  if (!std::isfinite(angle_rad)) return angle_rad;
  double a = std::remainder(angle_rad, 2.0 * kPi);  // [-pi, pi]
  if (a <= -kPi) a += 2.0 * kPi;
  return a;
}

PoseError error_in_measured_frame(const BasePose& reference, const BasePose& measured) {
  const double dx = reference.x_m - measured.x_m;
  const double dy = reference.y_m - measured.y_m;
  const double c = std::cos(measured.yaw_rad);
  const double s = std::sin(measured.yaw_rad);
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(reference.yaw_rad - measured.yaw_rad)};
}

PoseError error_in_reference_frame(const BasePose& reference, const BasePose& measured) {
  const double dx = reference.x_m - measured.x_m;
  const double dy = reference.y_m - measured.y_m;
  const double c = std::cos(reference.yaw_rad);
  const double s = std::sin(reference.yaw_rad);
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(reference.yaw_rad - measured.yaw_rad)};
}

BaseCommand tracking_law(const BaseReference& reference, const BasePose& measured,
                         const TrackingGains& gains) {
  const PoseError e = error_in_measured_frame(reference.pose, measured);
  const double v_r = reference.v_mps;
  BaseCommand cmd;
  cmd.v_mps = v_r * std::cos(e.yaw_rad) + gains.k_x_1ps * e.x_m;
  cmd.omega_radps = reference.omega_radps + v_r * gains.k_y_1pm2 * e.y_m +
                    (gains.k_yaw_1pm * std::abs(v_r) + gains.k_yaw_rest_1ps) * std::sin(e.yaw_rad);
  return cmd;
}

LimitedCommand limit_command(const BaseCommand& desired, const BaseCommand& previous, double dt_s,
                             const BaseLimits& limits) {
  LimitedCommand out;
  if (!std::isfinite(desired.v_mps) || !std::isfinite(desired.omega_radps)) {
    out.non_finite = true;
    return out;
  }
  const double r = limits.wheel_radius_m;
  const double half_track = 0.5 * limits.track_width_m;
  const double w_max = limits.wheel_omega_max_radps;
  // Wheel speeds of the desired command, rad/s.
  double wl = (desired.v_mps - half_track * desired.omega_radps) / r;
  double wr = (desired.v_mps + half_track * desired.omega_radps) / r;
  const double peak = std::max(std::abs(wl), std::abs(wr));
  if (peak > w_max) {
    const double scale = w_max / peak;
    wl *= scale;
    wr *= scale;
    out.speed_limited = true;
  }
  // Previous command's wheel speeds (a non-finite previous command counts as zero).
  double pl = (previous.v_mps - half_track * previous.omega_radps) / r;
  double pr = (previous.v_mps + half_track * previous.omega_radps) / r;
  if (!std::isfinite(pl) || !std::isfinite(pr)) pl = pr = 0.0;
  const double max_step = limits.wheel_alpha_max_radps2 * std::max(0.0, dt_s);
  const double dl = wl - pl;
  const double dr = wr - pr;
  const double step = std::max(std::abs(dl), std::abs(dr));
  if (step > max_step) {
    const double scale = step > 0.0 ? max_step / step : 0.0;
    wl = pl + dl * scale;
    wr = pr + dr * scale;
    out.accel_limited = true;
  }
  out.command.v_mps = 0.5 * r * (wl + wr);
  out.command.omega_radps = r * (wr - wl) / limits.track_width_m;
  return out;
}

BaseControl base_control(const BaseReference& reference, const BasePose& measured,
                         const BaseCommand& previous, double dt_s, const TrackingGains& gains,
                         const BaseLimits& limits) {
  BaseControl out;
  out.error = error_in_measured_frame(reference.pose, measured);
  out.unlimited = tracking_law(reference, measured, gains);
  out.limited = limit_command(out.unlimited, previous, dt_s, limits);
  return out;
}

}  // namespace porter::tracker
