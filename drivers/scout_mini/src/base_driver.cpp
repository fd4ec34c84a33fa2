#include "porter/scout_mini/base_driver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace porter::scout_mini {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kMaxEvents = 256;

double wrap_angle(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a - kPi;
}

std::string hex16(std::uint16_t v) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%04X", v);
  return buf;
}

std::string ms(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f ms", s * 1000.0);
  return buf;
}

std::string mode_name(int mode) {
  return mode < 0 ? std::string("unknown") : to_string(static_cast<ControlMode>(mode));
}

}  // namespace

VelocityCommand limit_command(const VelocityCommand& command, const DriverParams& p,
                              bool* limited) {
  VelocityCommand out = command;
  if (!std::isfinite(command.v_mps) || !std::isfinite(command.omega_radps)) {
    out.v_mps = out.omega_radps = 0.0;
    if (limited) *limited = true;
    return out;
  }
  double scale = 1.0;
  auto bound = [&scale](double value, double limit) {
    if (std::abs(value) > limit && std::abs(value) > 0) {
      scale = std::min(scale, limit / std::abs(value));
    }
  };
  bound(command.v_mps, p.v_max_mps);
  bound(command.omega_radps, p.omega_max_radps);
  const double wheel_max_mps = p.wheel_omega_max_radps * p.wheel_radius_m;
  const double half_track = 0.5 * p.track_width_m;
  bound(command.v_mps - command.omega_radps * half_track, wheel_max_mps);
  bound(command.v_mps + command.omega_radps * half_track, wheel_max_mps);
  out.v_mps = command.v_mps * scale;
  out.omega_radps = command.omega_radps * scale;
  if (limited) *limited = scale < 1.0;
  return out;
}

BaseDriver::BaseDriver(DriverParams params) : params_(params) {}

void BaseDriver::event(double t_s, EventLevel level, std::string message) {
  if (events_.size() >= kMaxEvents) {
    events_.pop_front();
    ++events_dropped_;
  }
  events_.push_back({t_s, level, std::move(message)});
}

std::vector<DriverEvent> BaseDriver::take_events() {
  std::vector<DriverEvent> out(events_.begin(), events_.end());
  events_.clear();
  return out;
}

void BaseDriver::on_frame(const CanFrame& frame, double t_s) {
  if (feedback_.refused_v1) return;
  const ProtocolHint hint = protocol_hint(frame);
  if (hint == ProtocolHint::v1) {
    if (!seen_v2_) {
      feedback_.refused_v1 = true;
      event(t_s, EventLevel::error,
            "the base speaks Agilex CAN protocol V1 (frame 0x151 seen before any V2 frame); "
            "porter-base drives protocol V2 only (0x111/0x211/0x221): refusing to command it. "
            "Update the base firmware to protocol V2 (Agilex) or use a V1 driver");
      return;
    }
    if (!v1_warned_) {
      v1_warned_ = true;
      event(t_s, EventLevel::warn, "a V1-only frame (0x151) on a V2 bus: ignored");
    }
    return;
  }
  if (hint == ProtocolHint::v2) seen_v2_ = true;

  DecodeStatus status = DecodeStatus::wrong_id;
  const std::uint32_t fid = frame.id;
  if (frame.extended) {
    ++unknown_;
    return;
  }
  if (fid == id::kSystemState) {
    SystemState st;
    status = decode_system_state(frame, st);
    if (status == DecodeStatus::ok) on_system_state(st, t_s);
  } else if (fid == id::kMotionState) {
    MotionState st;
    status = decode_motion_state(frame, st);
    if (status == DecodeStatus::ok) {
      feedback_.v_mps = st.v_mps;
      feedback_.omega_radps = st.omega_radps;
    }
  } else if (fid >= id::kActuatorHighSpeed1 && fid < id::kActuatorHighSpeed1 + kNumMotors) {
    ActuatorHighSpeed hs;
    status = decode_actuator_high_speed(frame, hs);
    if (status == DecodeStatus::ok) {
      feedback_.motor_speed_rpm[hs.motor] = hs.speed_rpm;
      feedback_.motor_current_a[hs.motor] = hs.current_a;
    }
  } else if (fid >= id::kActuatorLowSpeed1 && fid < id::kActuatorLowSpeed1 + kNumMotors) {
    ActuatorLowSpeed ls;
    status = decode_actuator_low_speed(frame, ls);
    if (status == DecodeStatus::ok) {
      const auto m = static_cast<std::size_t>(ls.motor);
      const std::uint8_t mask = static_cast<std::uint8_t>(~driver_bit::kDriverEnabled);
      const std::uint8_t was = feedback_.driver_status[m];
      if (((was ^ ls.driver_status) & mask) != 0) {
        const std::uint8_t raised = ls.driver_status & mask & ~was;
        const std::uint8_t cleared = was & mask & ~ls.driver_status;
        std::string text = "motor " + std::to_string(m + 1) + " driver status";
        if (raised) text += " raised: " + driver_status_names(raised);
        if (cleared) text += std::string(raised ? ";" : "") + " cleared: " + driver_status_names(cleared);
        event(t_s, raised ? EventLevel::warn : EventLevel::info, text);
      }
      feedback_.driver_status[m] = ls.driver_status;
      feedback_.driver_temperature_c[m] = ls.driver_temperature_c;
      feedback_.motor_temperature_c[m] = ls.motor_temperature_c;
    }
  } else if (fid == id::kOdometry) {
    Odometry odo;
    status = decode_odometry(frame, odo);
    if (status == DecodeStatus::ok) on_odometry(odo, t_s);
  } else if (fid == id::kBmsBasic) {
    BmsBasic bms;
    status = decode_bms_basic(frame, bms);
    if (status == DecodeStatus::ok) feedback_.battery_soc_pct = bms.soc_pct;
  } else if (fid == id::kMotionCommand || fid == id::kControlMode || fid == id::kErrorClear) {
    return;  // another commander on the bus (or an echo): not feedback
  } else {
    ++unknown_;
    return;
  }
  if (status != DecodeStatus::ok) {
    ++malformed_;
    return;
  }
  ++decoded_;
  last_feedback_t_s_ = t_s;
  if (frame.utime != 0) feedback_.feedback_utime = frame.utime;
  update_link(t_s);
}

void BaseDriver::on_system_state(const SystemState& st, double t_s) {
  if (st.control_mode != feedback_.control_mode) {
    const std::string from = mode_name(feedback_.control_mode);
    const std::string to = mode_name(st.control_mode);
    if (st.control_mode == static_cast<int>(ControlMode::can)) {
      event(t_s, EventLevel::info, "base in CAN command mode (was " + from + ")");
    } else if (st.control_mode == static_cast<int>(ControlMode::standby)) {
      const bool dropped_out = feedback_.control_mode == static_cast<int>(ControlMode::can);
      event(t_s, dropped_out ? EventLevel::warn : EventLevel::info,
            "base reports standby (was " + from +
                (dropped_out ? ": power cycle or mode change" : "") +
                "): sending 0x421 to enter CAN command mode");
    } else if (st.control_mode == static_cast<int>(ControlMode::remote)) {
      event(t_s, EventLevel::warn,
            "base under remote (RC) control, which overrides CAN (was " + from + ")");
    } else {
      event(t_s, EventLevel::warn, "base reports control mode " + to + " (was " + from +
                                       "): sending 0x421 to enter CAN command mode");
    }
    feedback_.control_mode = st.control_mode;
  }
  if (st.vehicle_state != feedback_.vehicle_state) {
    const VehicleState vs = static_cast<VehicleState>(st.vehicle_state);
    event(t_s, vs == VehicleState::normal ? EventLevel::info : EventLevel::error,
          "base vehicle state " + to_string(vs) +
              (feedback_.vehicle_state < 0
                   ? std::string()
                   : " (was " + to_string(static_cast<VehicleState>(feedback_.vehicle_state)) +
                         ")"));
    feedback_.vehicle_state = st.vehicle_state;
  }
  if (st.error_bits != feedback_.error_bits) {
    const std::uint16_t raised = st.error_bits & ~feedback_.error_bits;
    const std::uint16_t cleared = feedback_.error_bits & ~st.error_bits;
    if (raised) {
      event(t_s, (raised & error_bit::kFaults) ? EventLevel::error : EventLevel::warn,
            "base errors raised: " + error_names(raised) + " (error word " +
                hex16(st.error_bits) + ")");
    }
    if (cleared) {
      event(t_s, EventLevel::info, "base errors cleared: " + error_names(cleared) +
                                       " (error word " + hex16(st.error_bits) + ")");
    }
    feedback_.error_bits = st.error_bits;
  }
  feedback_.battery_voltage_v = st.battery_voltage_v;
}

void BaseDriver::on_odometry(const Odometry& odo, double t_s) {
  if (!have_odometry_) {
    have_odometry_ = true;
    last_odometry_ = odo;
    last_odometry_t_s_ = t_s;
    return;
  }
  // Differences in int32 arithmetic modulo 2^32: a counter wrap is a small step.
  const auto dl_mm = static_cast<std::int32_t>(static_cast<std::uint32_t>(odo.left_mm) -
                                               static_cast<std::uint32_t>(last_odometry_.left_mm));
  const auto dr_mm = static_cast<std::int32_t>(
      static_cast<std::uint32_t>(odo.right_mm) - static_cast<std::uint32_t>(last_odometry_.right_mm));
  last_odometry_ = odo;
  last_odometry_t_s_ = t_s;
  const double dl = dl_mm / 1000.0;
  const double dr = dr_mm / 1000.0;
  if (std::abs(dl) > params_.odometry_jump_m || std::abs(dr) > params_.odometry_jump_m) {
    event(t_s, EventLevel::warn,
          "wheel odometry counters jumped (left " + std::to_string(dl_mm) + " mm, right " +
              std::to_string(dr_mm) +
              " mm in one frame; the base restarted?): re-based, pose kept");
    return;
  }
  feedback_.wheel_left_m += dl;
  feedback_.wheel_right_m += dr;
  const double ds = 0.5 * (dl + dr);
  const double dyaw = params_.track_width_m > 0 ? (dr - dl) / params_.track_width_m : 0.0;
  const double mid = feedback_.odom_yaw_rad + 0.5 * dyaw;
  feedback_.odom_x_m += ds * std::cos(mid);
  feedback_.odom_y_m += ds * std::sin(mid);
  feedback_.odom_yaw_rad = wrap_angle(feedback_.odom_yaw_rad + dyaw);
}

void BaseDriver::update_link(double t_s) {
  const bool ok = t_s - last_feedback_t_s_ <= params_.feedback_timeout_s;
  if (ok == feedback_.link_ok) return;
  feedback_.link_ok = ok;
  if (ok) {
    event(t_s, EventLevel::info,
          link_ever_ok_ ? "CAN feedback restored" : "CAN feedback from the base received");
    link_ever_ok_ = true;
  } else {
    event(t_s, EventLevel::error, "CAN feedback lost (no frame for " +
                                      ms(params_.feedback_timeout_s) +
                                      "): sending zero velocity until it returns");
    // What the base reports is unknown until it speaks again.
    feedback_.control_mode = -1;
    feedback_.vehicle_state = -1;
  }
}

void BaseDriver::on_command(const VelocityCommand& command, double t_s) {
  command_ = command;
  command_t_s_ = t_s;
  if (!have_command_) {
    have_command_ = true;
    event(t_s, EventLevel::info, "first BASE_CMD received");
  }
}

void BaseDriver::on_estop(bool active, const std::string& cause, double t_s) {
  if (active == feedback_.estop_active) return;
  feedback_.estop_active = active;
  if (active) {
    event(t_s, EventLevel::error, "ESTOP engaged (" + cause + "): holding the base stopped");
  } else {
    estop_release_t_s_ = t_s;
    event(t_s, EventLevel::warn,
          "ESTOP released (" + cause + "): the base moves again on the next BASE_CMD");
  }
}

void BaseDriver::tick(double t_s, std::vector<CanFrame>& out) {
  update_link(t_s);
  if (feedback_.refused_v1) return;
  if (feedback_.control_mode != static_cast<int>(ControlMode::can) &&
      t_s - last_mode_sent_t_s_ >= params_.mode_retry_period_s - 1e-9) {
    out.push_back(encode_control_mode(ControlMode::can));
    last_mode_sent_t_s_ = t_s;
  }
  const bool fresh = have_command_ &&
                     t_s + params_.command_period_s <= command_t_s_ + params_.command_stale_s + 1e-9;
  if (have_command_ && fresh == feedback_.cmd_stale) {
    const double age = t_s - command_t_s_;
    event(t_s, fresh ? EventLevel::info : EventLevel::warn,
          fresh ? std::string("BASE_CMD fresh")
                : "BASE_CMD stale (last one " + ms(age) + " ago; a command drives the base "
                      "at most " + ms(params_.command_stale_s) + "): sending zero velocity");
  }
  feedback_.cmd_stale = !fresh;
  VelocityCommand send;
  const bool after_release = command_t_s_ > estop_release_t_s_;
  if (fresh && command_.enabled && !feedback_.estop_active && after_release &&
      feedback_.link_ok) {
    bool limited = false;
    send = limit_command(command_, params_, &limited);
    if (limited != limited_) {
      event(t_s, EventLevel::info,
            limited ? "BASE_CMD limited to the configured speed limits"
                    : "BASE_CMD within the limits again");
      limited_ = limited;
    }
    send.enabled = true;
  }
  MotionCommand motion;
  motion.v_mps = send.v_mps;
  motion.omega_radps = send.omega_radps;
  out.push_back(encode_motion_command(motion));
  last_sent_ = send;
}

void BaseDriver::stop_frames(std::vector<CanFrame>& out) const {
  if (feedback_.refused_v1) return;
  out.push_back(encode_motion_command(MotionCommand{}));
}

std::string BaseDriver::problem() const {
  if (feedback_.refused_v1) return "base speaks protocol V1: refused";
  if (!feedback_.link_ok) return "no CAN feedback from the base";
  if (feedback_.estop_active) return "ESTOP engaged";
  if (feedback_.vehicle_state > 0) {
    return "base vehicle state " + to_string(static_cast<VehicleState>(feedback_.vehicle_state));
  }
  if (feedback_.error_bits & error_bit::kFaults) {
    return "base errors: " + error_names(feedback_.error_bits);
  }
  if (feedback_.control_mode != static_cast<int>(ControlMode::can)) {
    return "base not in CAN command mode (" + mode_name(feedback_.control_mode) + ")";
  }
  return "";
}

}  // namespace porter::scout_mini
