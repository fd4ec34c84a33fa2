#include "porter/scout_mini/protocol.hpp"

#include <cmath>
#include <limits>

namespace porter::scout_mini {
namespace {

CanFrame make(std::uint32_t frame_id, std::uint8_t dlc) {
  CanFrame f;
  f.id = frame_id;
  f.dlc = dlc;
  return f;
}

void put_u16(CanFrame& f, int at, std::uint16_t v) {
  f.data[at] = static_cast<std::uint8_t>(v >> 8);
  f.data[at + 1] = static_cast<std::uint8_t>(v & 0xFF);
}
void put_i16(CanFrame& f, int at, std::int32_t v) { put_u16(f, at, static_cast<std::uint16_t>(v)); }
void put_i32(CanFrame& f, int at, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  f.data[at] = static_cast<std::uint8_t>(u >> 24);
  f.data[at + 1] = static_cast<std::uint8_t>(u >> 16);
  f.data[at + 2] = static_cast<std::uint8_t>(u >> 8);
  f.data[at + 3] = static_cast<std::uint8_t>(u);
}

std::uint16_t get_u16(const CanFrame& f, int at) {
  return static_cast<std::uint16_t>((f.data[at] << 8) | f.data[at + 1]);
}
std::int16_t get_i16(const CanFrame& f, int at) { return static_cast<std::int16_t>(get_u16(f, at)); }
std::int32_t get_i32(const CanFrame& f, int at) {
  const std::uint32_t u = (static_cast<std::uint32_t>(f.data[at]) << 24) |
                          (static_cast<std::uint32_t>(f.data[at + 1]) << 16) |
                          (static_cast<std::uint32_t>(f.data[at + 2]) << 8) |
                          static_cast<std::uint32_t>(f.data[at + 3]);
  return static_cast<std::int32_t>(u);
}

constexpr std::int32_t kI16Min = std::numeric_limits<std::int16_t>::min();
constexpr std::int32_t kI16Max = std::numeric_limits<std::int16_t>::max();

// The common checks: ID (exact or within [first, first + count)), standard data frame, length.
DecodeStatus check(const CanFrame& f, std::uint32_t first, std::uint32_t count, int min_dlc) {
  if (f.id < first || f.id >= first + count) return DecodeStatus::wrong_id;
  if (f.extended) return DecodeStatus::extended_id;
  if (f.rtr) return DecodeStatus::remote_frame;
  if (f.dlc < min_dlc || f.dlc > 8) return DecodeStatus::too_short;
  return DecodeStatus::ok;
}

std::string bit_names(std::uint32_t bits, const char* const* names, int count) {
  std::string s;
  for (int i = 0; i < 32; ++i) {
    if ((bits & (1u << i)) == 0) continue;
    if (!s.empty()) s += ", ";
    s += (i < count && names[i] != nullptr) ? std::string(names[i]) : "bit" + std::to_string(i);
  }
  return s;
}

}  // namespace

std::int32_t scale_round(double value, double scale, std::int32_t lo, std::int32_t hi) {
  const double x = value * scale;
  if (std::isnan(x)) return 0;
  if (x <= static_cast<double>(lo)) return lo;
  if (x >= static_cast<double>(hi)) return hi;
  return static_cast<std::int32_t>(std::lround(x));
}

std::string to_string(ControlMode mode) {
  switch (mode) {
    case ControlMode::standby: return "standby";
    case ControlMode::can: return "can";
    case ControlMode::serial: return "serial";
    case ControlMode::remote: return "remote";
  }
  return "unknown(" + std::to_string(static_cast<int>(mode)) + ")";
}

std::string to_string(VehicleState state) {
  switch (state) {
    case VehicleState::normal: return "normal";
    case VehicleState::estop: return "estop";
    case VehicleState::exception: return "exception";
  }
  return "unknown(" + std::to_string(static_cast<int>(state)) + ")";
}

const char* to_string(DecodeStatus status) {
  switch (status) {
    case DecodeStatus::ok: return "ok";
    case DecodeStatus::wrong_id: return "wrong_id";
    case DecodeStatus::remote_frame: return "remote_frame";
    case DecodeStatus::extended_id: return "extended_id";
    case DecodeStatus::too_short: return "too_short";
  }
  return "unknown";
}

std::string error_names(std::uint16_t bits) {
  static const char* const kNames[] = {
      "battery_under_voltage_fault", "battery_under_voltage_warning", "rc_signal_lost",
      "motor1_comm",                 "motor2_comm",                   "motor3_comm",
      "motor4_comm",                 "steer_encoder",                 "motor_driver",
      "high_level_comm"};
  return bit_names(bits, kNames, 10);
}

std::string driver_status_names(std::uint8_t bits) {
  static const char* const kNames[] = {"input_voltage_low", "motor_overheat", "driver_overload",
                                       "driver_overheat",   "sensor_fault",   "driver_fault",
                                       "driver_enabled",    "driver_reset"};
  return bit_names(bits, kNames, 8);
}

CanFrame encode_motion_command(const MotionCommand& c) {
  CanFrame f = make(id::kMotionCommand, 8);
  put_i16(f, 0, scale_round(c.v_mps, 1000.0, kI16Min, kI16Max));
  put_i16(f, 2, scale_round(c.omega_radps, 1000.0, kI16Min, kI16Max));
  put_i16(f, 4, scale_round(c.lateral_mps, 1000.0, kI16Min, kI16Max));
  put_i16(f, 6, scale_round(c.steering_rad, 1000.0, kI16Min, kI16Max));
  return f;
}

DecodeStatus decode_motion_command(const CanFrame& f, MotionCommand& out) {
  const DecodeStatus s = check(f, id::kMotionCommand, 1, 4);
  if (s != DecodeStatus::ok) return s;
  out = MotionCommand{};
  out.v_mps = get_i16(f, 0) / 1000.0;
  out.omega_radps = get_i16(f, 2) / 1000.0;
  if (f.dlc >= 6) out.lateral_mps = get_i16(f, 4) / 1000.0;
  if (f.dlc >= 8) out.steering_rad = get_i16(f, 6) / 1000.0;
  return s;
}

CanFrame encode_control_mode(ControlMode mode) {
  CanFrame f = make(id::kControlMode, 8);
  f.data[0] = static_cast<std::uint8_t>(mode);
  return f;
}

DecodeStatus decode_control_mode(const CanFrame& f, std::uint8_t& raw_mode) {
  const DecodeStatus s = check(f, id::kControlMode, 1, 1);
  if (s == DecodeStatus::ok) raw_mode = f.data[0];
  return s;
}

CanFrame encode_error_clear(std::uint8_t target) {
  CanFrame f = make(id::kErrorClear, 1);
  f.data[0] = target;
  return f;
}

DecodeStatus decode_error_clear(const CanFrame& f, std::uint8_t& target) {
  const DecodeStatus s = check(f, id::kErrorClear, 1, 1);
  if (s == DecodeStatus::ok) target = f.data[0];
  return s;
}

CanFrame encode_system_state(const SystemState& st) {
  CanFrame f = make(id::kSystemState, 8);
  f.data[0] = st.vehicle_state;
  f.data[1] = st.control_mode;
  put_u16(f, 2, static_cast<std::uint16_t>(scale_round(st.battery_voltage_v, 10.0, 0, 0xFFFF)));
  put_u16(f, 4, st.error_bits);
  f.data[7] = st.count;
  return f;
}

DecodeStatus decode_system_state(const CanFrame& f, SystemState& out) {
  const DecodeStatus s = check(f, id::kSystemState, 1, 6);
  if (s != DecodeStatus::ok) return s;
  out = SystemState{};
  out.vehicle_state = f.data[0];
  out.control_mode = f.data[1];
  out.battery_voltage_v = get_u16(f, 2) / 10.0;
  out.error_bits = get_u16(f, 4);
  if (f.dlc >= 8) out.count = f.data[7];
  return s;
}

CanFrame encode_motion_state(const MotionState& st) {
  CanFrame f = make(id::kMotionState, 8);
  put_i16(f, 0, scale_round(st.v_mps, 1000.0, kI16Min, kI16Max));
  put_i16(f, 2, scale_round(st.omega_radps, 1000.0, kI16Min, kI16Max));
  put_i16(f, 4, scale_round(st.lateral_mps, 1000.0, kI16Min, kI16Max));
  put_i16(f, 6, scale_round(st.steering_rad, 1000.0, kI16Min, kI16Max));
  return f;
}

DecodeStatus decode_motion_state(const CanFrame& f, MotionState& out) {
  const DecodeStatus s = check(f, id::kMotionState, 1, 4);
  if (s != DecodeStatus::ok) return s;
  out = MotionState{};
  out.v_mps = get_i16(f, 0) / 1000.0;
  out.omega_radps = get_i16(f, 2) / 1000.0;
  if (f.dlc >= 6) out.lateral_mps = get_i16(f, 4) / 1000.0;
  if (f.dlc >= 8) out.steering_rad = get_i16(f, 6) / 1000.0;
  return s;
}

CanFrame encode_actuator_high_speed(const ActuatorHighSpeed& st) {
  const int motor = st.motor < 0 ? 0 : (st.motor >= kNumMotors ? kNumMotors - 1 : st.motor);
  CanFrame f = make(id::kActuatorHighSpeed1 + static_cast<std::uint32_t>(motor), 8);
  put_i16(f, 0, scale_round(st.speed_rpm, 1.0, kI16Min, kI16Max));
  put_i16(f, 2, scale_round(st.current_a, 10.0, kI16Min, kI16Max));
  put_i32(f, 4, st.pulse_count);
  return f;
}

DecodeStatus decode_actuator_high_speed(const CanFrame& f, ActuatorHighSpeed& out) {
  const DecodeStatus s = check(f, id::kActuatorHighSpeed1, kNumMotors, 8);
  if (s != DecodeStatus::ok) return s;
  out.motor = static_cast<int>(f.id - id::kActuatorHighSpeed1);
  out.speed_rpm = get_i16(f, 0);
  out.current_a = get_i16(f, 2) / 10.0;
  out.pulse_count = get_i32(f, 4);
  return s;
}

CanFrame encode_actuator_low_speed(const ActuatorLowSpeed& st) {
  const int motor = st.motor < 0 ? 0 : (st.motor >= kNumMotors ? kNumMotors - 1 : st.motor);
  CanFrame f = make(id::kActuatorLowSpeed1 + static_cast<std::uint32_t>(motor), 8);
  put_u16(f, 0, static_cast<std::uint16_t>(scale_round(st.driver_voltage_v, 10.0, 0, 0xFFFF)));
  put_i16(f, 2, scale_round(st.driver_temperature_c, 1.0, kI16Min, kI16Max));
  f.data[4] = static_cast<std::uint8_t>(
      static_cast<std::int8_t>(scale_round(st.motor_temperature_c, 1.0, -128, 127)));
  f.data[5] = st.driver_status;
  return f;
}

DecodeStatus decode_actuator_low_speed(const CanFrame& f, ActuatorLowSpeed& out) {
  const DecodeStatus s = check(f, id::kActuatorLowSpeed1, kNumMotors, 6);
  if (s != DecodeStatus::ok) return s;
  out.motor = static_cast<int>(f.id - id::kActuatorLowSpeed1);
  out.driver_voltage_v = get_u16(f, 0) / 10.0;
  out.driver_temperature_c = get_i16(f, 2);
  out.motor_temperature_c = static_cast<std::int8_t>(f.data[4]);
  out.driver_status = f.data[5];
  return s;
}

CanFrame encode_odometry(const Odometry& o) {
  CanFrame f = make(id::kOdometry, 8);
  put_i32(f, 0, o.left_mm);
  put_i32(f, 4, o.right_mm);
  return f;
}

DecodeStatus decode_odometry(const CanFrame& f, Odometry& out) {
  const DecodeStatus s = check(f, id::kOdometry, 1, 8);
  if (s != DecodeStatus::ok) return s;
  out.left_mm = get_i32(f, 0);
  out.right_mm = get_i32(f, 4);
  return s;
}

CanFrame encode_bms_basic(const BmsBasic& b) {
  CanFrame f = make(id::kBmsBasic, 8);
  f.data[0] = static_cast<std::uint8_t>(scale_round(b.soc_pct, 1.0, 0, 255));
  f.data[1] = static_cast<std::uint8_t>(scale_round(b.soh_pct, 1.0, 0, 255));
  put_i16(f, 2, scale_round(b.voltage_v, 10.0, kI16Min, kI16Max));
  put_i16(f, 4, scale_round(b.current_a, 10.0, kI16Min, kI16Max));
  put_i16(f, 6, scale_round(b.temperature_c, 10.0, kI16Min, kI16Max));
  return f;
}

DecodeStatus decode_bms_basic(const CanFrame& f, BmsBasic& out) {
  const DecodeStatus s = check(f, id::kBmsBasic, 1, 8);
  if (s != DecodeStatus::ok) return s;
  out.soc_pct = f.data[0];
  out.soh_pct = f.data[1];
  out.voltage_v = get_i16(f, 2) / 10.0;
  out.current_a = get_i16(f, 4) / 10.0;
  out.temperature_c = get_i16(f, 6) / 10.0;
  return s;
}

ProtocolHint protocol_hint(const CanFrame& f) {
  if (f.extended) return ProtocolHint::none;
  if (f.id == id::kV1Feedback) return ProtocolHint::v1;
  if (f.id == id::kMotionState || f.id == id::kRcState) return ProtocolHint::v2;
  return ProtocolHint::none;
}

}  // namespace porter::scout_mini
