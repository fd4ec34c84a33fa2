#include "porter/tracker/tracker.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace porter::tracker {
namespace {

std::string fmt(const char* format, double a, double b = 0.0) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, format, a, b);
  return buffer;
}

// Text from the network echoed in messages: printable ASCII only (an embedded NUL would make the
// status message fail to encode), at most 64 characters.
std::string printable(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (out.size() == 64) {
      out += "...";
      break;
    }
    out += (c >= 0x20 && c < 0x7f) ? c : '?';
  }
  return out;
}

bool finite_pose(const BasePose& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.yaw_rad);
}

}  // namespace

const char* to_string(TrackerState state) {
  switch (state) {
    case TrackerState::idle: return "IDLE";
    case TrackerState::tracking: return "TRACKING";
    case TrackerState::finished: return "FINISHED";
    case TrackerState::stale_state: return "STALE_STATE";
    case TrackerState::stale_trajectory: return "STALE_TRAJECTORY";
    case TrackerState::estop: return "E-STOP";
    case TrackerState::fault: return "FAULT";
  }
  return "UNKNOWN";
}

void TrackerParams::validate() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("TrackerParams: ") + what);
  };
  require(gains.k_x_1ps > 0.0 && std::isfinite(gains.k_x_1ps), "gains.k_x_1ps must be > 0");
  require(gains.k_y_1pm2 > 0.0 && std::isfinite(gains.k_y_1pm2), "gains.k_y_1pm2 must be > 0");
  require(gains.k_yaw_1pm >= 0.0 && std::isfinite(gains.k_yaw_1pm), "gains.k_yaw_1pm must be >= 0");
  require(gains.k_yaw_rest_1ps >= 0.0 && std::isfinite(gains.k_yaw_rest_1ps),
          "gains.k_yaw_rest_1ps must be >= 0");
  require(base_limits.wheel_radius_m > 0.0, "base_limits.wheel_radius_m must be > 0");
  require(base_limits.track_width_m > 0.0, "base_limits.track_width_m must be > 0");
  require(base_limits.wheel_omega_max_radps > 0.0, "base_limits.wheel_omega_max_radps must be > 0");
  require(base_limits.wheel_alpha_max_radps2 > 0.0,
          "base_limits.wheel_alpha_max_radps2 must be > 0");
  require((joint_velocity_max_radps.array() > 0.0).all(), "joint_velocity_max_radps must be > 0");
  require(!frame_id.empty(), "frame_id must not be empty");
  require(period_s > 0.0 && period_s < 1.0, "period_s must be in (0, 1)");
  require(state_timeout_s > 0.0, "state_timeout_s must be > 0");
  require(trajectory_timeout_s >= 0.0, "trajectory_timeout_s must be >= 0");
  require(trajectory_max_age_s > 0.0, "trajectory_max_age_s must be > 0");
  require(max_start_lag_s >= 0.0, "max_start_lag_s must be >= 0");
  require(max_position_error_m > 0.0, "max_position_error_m must be > 0");
  require(max_yaw_error_rad > 0.0, "max_yaw_error_rad must be > 0");
}

Tracker::Tracker(TrackerParams params) : params_(std::move(params)) {
  params_.validate();
  out_.message = "no trajectory";
}

void Tracker::on_state(const MeasuredState& state, std::int64_t receive_utime) {
  state_ = state;
  state_receive_utime_ = receive_utime;
}

OfferResult Tracker::on_trajectory(TrajectoryOffer offer, std::int64_t receive_utime) {
  OfferResult result;
  auto refuse = [&](std::string reason) {
    ++refused_;
    last_refusal_ = "plan " + std::to_string(offer.plan_id) + " refused: " + reason;
    result.reason = std::move(reason);
    return result;
  };
  if (estop_latched_) return refuse("e-stop engaged");
  if (offer.frame_id != params_.frame_id) {
    return refuse("frame '" + printable(offer.frame_id) + "', expected '" + params_.frame_id + "'");
  }
  const double age_s = static_cast<double>(receive_utime - offer.utime) * 1e-6;
  if (age_s > params_.trajectory_max_age_s) {
    return refuse(fmt("message is %.3f s old (limit %.3f s)", age_s, params_.trajectory_max_age_s));
  }
  const double lag_s = static_cast<double>(receive_utime - offer.start_utime) * 1e-6;
  if (lag_s > params_.max_start_lag_s) {
    return refuse(fmt("start lies %.3f s in the past (limit %.3f s)", lag_s,
                      params_.max_start_lag_s));
  }
  last_trajectory_receive_utime_ = receive_utime;
  pending_ = Active{std::move(offer), receive_utime};
  result.accepted = true;
  return result;
}

void Tracker::on_invalid_trajectory(std::int64_t plan_id, const std::string& reason) {
  ++refused_;
  last_refusal_ = "plan " + std::to_string(plan_id) + " refused: " + printable(reason);
}

void Tracker::on_estop(bool active, const std::string& reason, std::int64_t receive_utime) {
  if (active) {
    if (!estop_latched_) {
      estop_reason_ = reason.empty() ? std::string("ESTOP active") : printable(reason);
    }
    estop_latched_ = true;
    return;
  }
  if (estop_latched_) {
    estop_latched_ = false;
    active_.reset();
    pending_.reset();
    fault_ = false;
    release_note_ = "e-stop released; waiting for a new trajectory";
  }
}

void Tracker::set_state(TrackerState state, std::string message) {
  out_.state = state;
  out_.state_changed = !stepped_ || state != previous_state_;
  if (out_.state_changed) out_.message = std::move(message);
}

void Tracker::command_zero() {
  out_.base_enabled = false;
  out_.base = BaseCommand{};
  out_.base_speed_limited = false;
  out_.base_accel_limited = false;
  out_.arm_enabled = false;
  out_.qd_radps.setZero();
  last_command_ = BaseCommand{};
}

std::string Tracker::state_problem(std::int64_t now_utime) const {
  if (!state_) return "no ROBOT_STATE received";
  const double age_s = static_cast<double>(now_utime - state_receive_utime_) * 1e-6;
  if (age_s > params_.state_timeout_s) {
    return fmt("ROBOT_STATE is %.3f s old (limit %.3f s)", age_s, params_.state_timeout_s);
  }
  if (!state_->pose_valid) return "ROBOT_STATE pose is not valid";
  if (!state_->base_valid) return "ROBOT_STATE base is not valid";
  if (!finite_pose(state_->pose)) return "ROBOT_STATE pose is not finite";
  if (params_.require_arm_state) {
    if (!state_->arm_valid) return "ROBOT_STATE arm is not valid";
    if (state_->num_joints != kNumArmJoints) {
      return "ROBOT_STATE has " + std::to_string(state_->num_joints) + " joints, expected " +
             std::to_string(kNumArmJoints);
    }
    if (!state_->q_rad.allFinite()) return "ROBOT_STATE joint angles are not finite";
  }
  return {};
}

const TrackerOutput& Tracker::step(std::int64_t now_utime) {
  double dt_s = stepped_ ? static_cast<double>(now_utime - last_step_utime_) * 1e-6
                         : params_.period_s;
  dt_s = std::clamp(dt_s, 0.0, 10.0 * params_.period_s);
  previous_state_ = out_.state;
  out_.utime = now_utime;

  // Hand-off: a pending trajectory whose start has come replaces the active one.
  if (pending_ && now_utime >= pending_->offer.start_utime) {
    active_ = std::move(pending_);
    pending_.reset();
    fault_ = false;
    release_note_.clear();
  }
  out_.plan_id = active_ ? active_->offer.plan_id : -1;
  out_.duration_s = active_ ? active_->offer.trajectory.total_duration_s() : 0.0;
  out_.t_s = active_ ? static_cast<double>(now_utime - active_->offer.start_utime) * 1e-6 : 0.0;

  const bool state_estop = state_ && state_->estop_active &&
                           static_cast<double>(now_utime - state_receive_utime_) * 1e-6 <=
                               params_.state_timeout_s;
  if (estop_latched_ || state_estop) {
    command_zero();
    set_state(TrackerState::estop,
              estop_latched_ ? "ESTOP: " + estop_reason_ : "ROBOT_STATE reports an engaged e-stop");
  } else if (!active_) {
    command_zero();
    set_state(TrackerState::idle, release_note_.empty() ? "no trajectory" : release_note_);
  } else if (std::string problem = state_problem(now_utime); !problem.empty()) {
    command_zero();
    set_state(TrackerState::stale_state, std::move(problem));
  } else if (params_.trajectory_timeout_s > 0.0 &&
             static_cast<double>(now_utime - last_trajectory_receive_utime_) * 1e-6 >
                 params_.trajectory_timeout_s) {
    command_zero();
    set_state(TrackerState::stale_trajectory,
              fmt("no TRAJECTORY for %.3f s (limit %.3f s)",
                  static_cast<double>(now_utime - last_trajectory_receive_utime_) * 1e-6,
                  params_.trajectory_timeout_s));
  } else if (fault_) {
    command_zero();
    set_state(TrackerState::fault, fault_message_);
  } else {
    const Trajectory& traj = active_->offer.trajectory;
    const bool finished = out_.t_s >= out_.duration_s;
    const double t_eval = std::clamp(out_.t_s, 0.0, out_.duration_s);
    const TrajectoryState sample = traj.sample(t_eval, params_.base_limits);
    BaseReference ref;
    ref.pose = {sample.z[0], sample.z[1], sample.base.yaw_rad};
    ref.v_mps = finished ? 0.0 : sample.base.signed_speed_mps;
    ref.omega_radps = finished ? 0.0 : sample.base.yaw_rate_radps;
    const JointVector q_ref = sample.z.tail<kNumArmJoints>();
    out_.error_reference_frame = error_in_reference_frame(ref.pose, state_->pose);
    out_.q_error_rad = q_ref - state_->q_rad;
    const double position_error_m =
        std::hypot(out_.error_reference_frame.x_m, out_.error_reference_frame.y_m);
    const double yaw_error_rad = std::abs(out_.error_reference_frame.yaw_rad);
    const bool sample_finite = sample.z.allFinite() && sample.z_dot.allFinite() &&
                               std::isfinite(ref.pose.yaw_rad) && std::isfinite(ref.v_mps) &&
                               std::isfinite(ref.omega_radps);
    if (!sample_finite) {
      // Finite coefficients can still overflow when evaluated (huge values from the network).
      fault_ = true;
      fault_message_ = fmt("trajectory sample at t = %.3f s is not finite; waiting for a new "
                           "trajectory", t_eval);
      command_zero();
      set_state(TrackerState::fault, fault_message_);
    } else if (!finished && (position_error_m > params_.max_position_error_m ||
                             yaw_error_rad > params_.max_yaw_error_rad)) {
      fault_ = true;
      fault_message_ = fmt("tracking error %.3f m, %.3f rad beyond the limits", position_error_m,
                           yaw_error_rad) +
                       fmt(" (%.3f m, %.3f rad); waiting for a new trajectory",
                           params_.max_position_error_m, params_.max_yaw_error_rad);
      command_zero();
      set_state(TrackerState::fault, fault_message_);
    } else if (finished) {
      out_.base_enabled = true;
      out_.base = BaseCommand{};
      out_.base_speed_limited = out_.base_accel_limited = false;
      last_command_ = out_.base;
      out_.arm_enabled = true;
      out_.q_rad = q_ref;
      out_.qd_radps.setZero();
      set_state(TrackerState::finished, "trajectory finished; holding the final pose");
    } else {
      const BaseControl control = base_control(ref, state_->pose, last_command_, dt_s,
                                               params_.gains, params_.base_limits);
      out_.base_enabled = !control.limited.non_finite;
      out_.base = control.limited.command;
      out_.base_speed_limited = control.limited.speed_limited;
      out_.base_accel_limited = control.limited.accel_limited;
      last_command_ = out_.base;
      out_.arm_enabled = q_ref.allFinite();
      out_.q_rad = q_ref;
      const JointVector qd_ref = sample.z_dot.tail<kNumArmJoints>();
      out_.qd_radps = qd_ref.cwiseMax(-params_.joint_velocity_max_radps)
                          .cwiseMin(params_.joint_velocity_max_radps);
      set_state(TrackerState::tracking, std::string());
    }
  }
  stepped_ = true;
  last_step_utime_ = now_utime;
  return out_;
}

}  // namespace porter::tracker
