#include "porter/scout_mini/firmware.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace porter::scout_mini {
namespace {

constexpr double kPi = 3.14159265358979323846;

double wrap_angle(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a - kPi;
}

// One lag-and-rate-limited step of `value` toward `target`.
double follow(double value, double target, double tau_s, double rate_max, double settle,
              double dt) {
  const double error = target - value;
  // Within the settle band: onto the target, still no faster than the rate limit.
  if (std::abs(error) <= settle) return value + std::clamp(error, -rate_max * dt, rate_max * dt);
  double rate = tau_s > 0 ? error / tau_s : error / dt;
  rate = std::clamp(rate, -rate_max, rate_max);
  const double next = value + rate * dt;
  // Never step past the target.
  if ((target - next) * error < 0) return target;
  return next;
}

std::int64_t sim_utime(double t_s) { return static_cast<std::int64_t>(std::llround(t_s * 1e6)); }

}  // namespace

ScoutMiniFirmware::ScoutMiniFirmware(FirmwareParams params, PlanarPose initial_pose)
    : params_(params), pose_(initial_pose) {
  const std::array<bool, kNumMotors> on{true, true, true, true};
  streams_ = {
      {id::kSystemState, 1, params_.system_state_period_s, on},
      {id::kMotionState, 1, params_.motion_state_period_s, on},
      {id::kActuatorHighSpeed1, kNumMotors, params_.actuator_period_s, on},
      {id::kActuatorLowSpeed1, kNumMotors, params_.actuator_period_s, on},
      {id::kOdometry, 1, params_.odometry_period_s, on},
      {id::kBmsBasic, 1, params_.bms_period_s, on},
  };
  boot(0.0);
}

void ScoutMiniFirmware::boot(double t_s) {
  powered_ = true;
  mode_ = ControlMode::standby;
  errors_ = 0;
  command_ = MotionCommand{};
  last_command_s_ = -1e300;
  v_mps_ = omega_radps_ = 0.0;
  accel_left_mps2_ = accel_right_mps2_ = 0.0;
  left_m_ = right_m_ = 0.0;
  system_count_ = 0;
  for (Stream& s : streams_) {
    s.origin_s = t_s;
    s.index = 1;
  }
}

VehicleState ScoutMiniFirmware::vehicle_state() const {
  if (estop_button_) return VehicleState::estop;
  if ((errors_ & error_bit::kFaults) != 0) return VehicleState::exception;
  return VehicleState::normal;
}

MotionCommand ScoutMiniFirmware::target() const {
  MotionCommand target;
  if (!powered_ || mode_ != ControlMode::can || vehicle_state() != VehicleState::normal) {
    return target;
  }
  if (t_s_ - last_command_s_ > params_.command_timeout_s) return target;
  target.v_mps = std::clamp(command_.v_mps, -params_.v_max_mps, params_.v_max_mps);
  target.omega_radps =
      std::clamp(command_.omega_radps, -params_.omega_max_radps, params_.omega_max_radps);
  return target;
}

void ScoutMiniFirmware::receive(const CanFrame& frame, double t_s) {
  if (inputs_.size() >= std::max<std::size_t>(1, params_.input_queue_capacity)) {
    inputs_.pop_front();
    ++dropped_;
  }
  inputs_.emplace_back(t_s >= t_s_ ? t_s : t_s_, frame);  // NaN or past: now
}

void ScoutMiniFirmware::process(const CanFrame& frame, double t_s) {
  if (!powered_) return;
  ++received_;
  switch (frame.id) {
    case id::kControlMode: {
      std::uint8_t raw = 0;
      if (decode_control_mode(frame, raw) == DecodeStatus::ok && raw <= 2) {
        mode_ = static_cast<ControlMode>(raw);
        return;
      }
      break;
    }
    case id::kMotionCommand: {
      MotionCommand command;
      if (mode_ == ControlMode::can &&
          decode_motion_command(frame, command) == DecodeStatus::ok) {
        command_ = command;
        last_command_s_ = t_s;
        return;
      }
      break;
    }
    case id::kErrorClear: {
      std::uint8_t target = 0;
      if (mode_ == ControlMode::can && decode_error_clear(frame, target) == DecodeStatus::ok) {
        if (target == 0) {
          errors_ = 0;
          return;
        }
        if (target <= kNumMotors) {
          errors_ &= static_cast<std::uint16_t>(~(error_bit::kMotor1Comm << (target - 1)));
          return;
        }
      }
      break;
    }
    default:
      break;
  }
  ++ignored_;
}

void ScoutMiniFirmware::step(double dt) {
  const MotionCommand goal = target();
  const double v0 = v_mps_;
  const double w0 = omega_radps_;
  if (!powered_) {
    v_mps_ = omega_radps_ = 0.0;
  } else {
    v_mps_ = follow(v_mps_, goal.v_mps, params_.time_constant_s, params_.linear_accel_max_mps2,
                    params_.settle_mps, dt);
    omega_radps_ = follow(omega_radps_, goal.omega_radps, params_.time_constant_s,
                          params_.angular_accel_max_radps2, params_.settle_radps, dt);
  }
  const double half_track = 0.5 * params_.track_width_m;
  accel_left_mps2_ = ((v_mps_ - omega_radps_ * half_track) - (v0 - w0 * half_track)) / dt;
  accel_right_mps2_ = ((v_mps_ + omega_radps_ * half_track) - (v0 + w0 * half_track)) / dt;
  // Trapezoidal speeds over the step, exact arc for the pose.
  const double v = 0.5 * (v0 + v_mps_);
  const double w = 0.5 * (w0 + omega_radps_);
  left_m_ += (v - w * half_track) * dt;
  right_m_ += (v + w * half_track) * dt;
  const double yaw0 = pose_.yaw_rad;
  if (std::abs(w) < 1e-9) {
    pose_.x_m += v * std::cos(yaw0) * dt;
    pose_.y_m += v * std::sin(yaw0) * dt;
  } else {
    const double yaw1 = yaw0 + w * dt;
    pose_.x_m += v / w * (std::sin(yaw1) - std::sin(yaw0));
    pose_.y_m -= v / w * (std::cos(yaw1) - std::cos(yaw0));
  }
  pose_.yaw_rad = wrap_angle(yaw0 + w * dt);
}

void ScoutMiniFirmware::integrate(double until_s) {
  const double h = params_.physics_step_s > 0 ? params_.physics_step_s : 0.001;
  while (t_s_ < until_s) {
    const double dt = std::min(h, until_s - t_s_);
    if (dt <= 0) break;
    t_s_ += dt;
    step(dt);
    if (until_s - t_s_ < 1e-12) t_s_ = until_s;
  }
}

double ScoutMiniFirmware::next_event(double limit_s) const {
  double next = limit_s;
  if (!inputs_.empty()) next = std::min(next, inputs_.front().first);
  if (!powered_) {
    next = std::min(next, power_on_at_s_);
  } else {
    for (const Stream& s : streams_) next = std::min(next, s.next_s());
  }
  return std::max(next, t_s_);
}

void ScoutMiniFirmware::advance(double t_s, std::vector<CanFrame>& out) {
  if (!(t_s >= t_s_) || !std::isfinite(t_s)) return;  // time never goes backwards
  for (;;) {
    const double at = next_event(t_s);
    integrate(at);
    t_s_ = at;
    if (!powered_ && power_on_at_s_ <= t_s_) boot(power_on_at_s_);
    while (!inputs_.empty() && inputs_.front().first <= t_s_) {
      process(inputs_.front().second, t_s_);
      inputs_.pop_front();
    }
    if (powered_) {
      for (Stream& s : streams_) {
        if (s.next_s() <= t_s_ + 1e-9) {
          emit(s, out);
          ++s.index;
          // After a long gap (a stalled caller), resume on the grid without a burst.
          while (s.next_s() <= t_s_ + 1e-9) ++s.index;
        }
      }
    }
    if (t_s_ >= t_s) break;
  }
}

void ScoutMiniFirmware::emit(Stream& stream, std::vector<CanFrame>& out) {
  const double half_track = 0.5 * params_.track_width_m;
  const double v_left = v_mps_ - omega_radps_ * half_track;
  const double v_right = v_mps_ + omega_radps_ * half_track;
  const double r = params_.wheel_radius_m > 0 ? params_.wheel_radius_m : 1.0;
  auto push = [&](CanFrame f) {
    f.utime = sim_utime(t_s_);
    out.push_back(f);
  };
  switch (stream.first_id) {
    case id::kSystemState: {
      if (!stream.enabled[0]) return;
      SystemState st;
      st.vehicle_state = static_cast<std::uint8_t>(vehicle_state());
      st.control_mode = static_cast<std::uint8_t>(mode_);
      st.battery_voltage_v = params_.battery_voltage_v;
      st.error_bits = errors_;
      st.count = system_count_++;
      push(encode_system_state(st));
      return;
    }
    case id::kMotionState: {
      if (!stream.enabled[0]) return;
      MotionState st;
      st.v_mps = v_mps_;
      st.omega_radps = omega_radps_;
      push(encode_motion_state(st));
      return;
    }
    case id::kActuatorHighSpeed1:
    case id::kActuatorLowSpeed1: {
      for (int m = 0; m < kNumMotors; ++m) {
        if (!stream.enabled[m]) continue;
        const bool right = m == 0 || m == 3;
        if (stream.first_id == id::kActuatorHighSpeed1) {
          const double wheel_m = right ? right_m_ : left_m_;
          const double speed = right ? v_right : v_left;
          const double accel = right ? accel_right_mps2_ : accel_left_mps2_;
          ActuatorHighSpeed hs;
          hs.motor = m;
          hs.speed_rpm = speed / r * params_.gear_ratio * 60.0 / (2.0 * kPi);
          hs.current_a = (std::abs(speed) > 1e-6 || std::abs(accel) > 1e-6)
                             ? std::copysign(params_.idle_current_a, speed) +
                                   params_.accel_current_a_per_mps2 * accel
                             : 0.0;
          const double pulses =
              wheel_m / r / (2.0 * kPi) * params_.gear_ratio * params_.pulses_per_motor_rev;
          hs.pulse_count = static_cast<std::int32_t>(
              static_cast<std::uint32_t>(static_cast<std::int64_t>(std::llround(pulses))));
          push(encode_actuator_high_speed(hs));
        } else {
          ActuatorLowSpeed ls;
          ls.motor = m;
          ls.driver_voltage_v = params_.battery_voltage_v;
          ls.driver_temperature_c = params_.driver_temperature_c;
          ls.motor_temperature_c = params_.motor_temperature_c;
          ls.driver_status = driver_bit::kDriverEnabled;
          push(encode_actuator_low_speed(ls));
        }
      }
      return;
    }
    case id::kOdometry: {
      if (!stream.enabled[0]) return;
      Odometry o;
      o.left_mm = static_cast<std::int32_t>(
          static_cast<std::uint32_t>(static_cast<std::int64_t>(std::llround(left_m_ * 1000.0))));
      o.right_mm = static_cast<std::int32_t>(
          static_cast<std::uint32_t>(static_cast<std::int64_t>(std::llround(right_m_ * 1000.0))));
      push(encode_odometry(o));
      return;
    }
    case id::kBmsBasic: {
      if (!stream.enabled[0]) return;
      BmsBasic b;
      b.soc_pct = params_.battery_soc_pct;
      b.soh_pct = 100.0;
      b.voltage_v = params_.battery_voltage_v;
      b.current_a = 1.0;
      b.temperature_c = 25.0;
      push(encode_bms_basic(b));
      return;
    }
    default:
      return;
  }
}

bool ScoutMiniFirmware::power_cycle(double t_s, double off_s) {
  if (!(off_s >= 0.0) || !std::isfinite(off_s)) return false;
  // Power is cut now (the caller passes the current simulated time).
  powered_ = false;
  v_mps_ = omega_radps_ = 0.0;
  inputs_.clear();
  power_on_at_s_ = std::max(t_s, t_s_) + off_s;
  return true;
}

bool ScoutMiniFirmware::set_stream_enabled(std::uint32_t can_id, bool enabled) {
  for (Stream& s : streams_) {
    if (can_id >= s.first_id && can_id < s.first_id + static_cast<std::uint32_t>(s.count)) {
      s.enabled[can_id - s.first_id] = enabled;
      return true;
    }
  }
  return false;
}

bool ScoutMiniFirmware::raise_error(std::uint32_t code) {
  if (code == 0 || code > 0xFFFF) return false;
  errors_ |= static_cast<std::uint16_t>(code);
  return true;
}

bool ScoutMiniFirmware::clear_errors() {
  errors_ = 0;
  return true;
}

}  // namespace porter::scout_mini
