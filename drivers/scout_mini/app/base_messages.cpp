#include "base_messages.hpp"

namespace porter::scout_mini {

VelocityCommand to_command(const porter::base_cmd_t& msg) {
  VelocityCommand c;
  c.enabled = msg.enabled;
  c.v_mps = msg.v_mps;
  c.omega_radps = msg.omega_radps;
  return c;
}

porter::base_state_t to_base_state(const BaseFeedback& fb, std::int64_t utime) {
  porter::base_state_t msg;
  msg.utime = utime;
  msg.v_mps = fb.v_mps;
  msg.omega_radps = fb.omega_radps;
  msg.wheel_left_m = fb.wheel_left_m;
  msg.wheel_right_m = fb.wheel_right_m;
  msg.odom_x_m = fb.odom_x_m;
  msg.odom_y_m = fb.odom_y_m;
  msg.odom_yaw_rad = fb.odom_yaw_rad;
  msg.num_motors = kNumMotors;
  msg.motor_speed_rpm.assign(fb.motor_speed_rpm.begin(), fb.motor_speed_rpm.end());
  msg.motor_current_a.assign(fb.motor_current_a.begin(), fb.motor_current_a.end());
  msg.driver_temperature_c.assign(fb.driver_temperature_c.begin(), fb.driver_temperature_c.end());
  msg.battery_voltage_v = fb.battery_voltage_v;
  msg.battery_soc_pct = fb.battery_soc_pct;
  msg.vehicle_state = fb.vehicle_state < 0 || fb.vehicle_state > 2
                          ? porter::base_state_t::VEHICLE_UNKNOWN
                          : static_cast<std::int8_t>(fb.vehicle_state);
  msg.control_mode = fb.control_mode < 0 || fb.control_mode > 3
                         ? porter::base_state_t::MODE_UNKNOWN
                         : static_cast<std::int8_t>(fb.control_mode);
  msg.fault_bits = fb.error_bits;
  msg.cmd_stale = fb.cmd_stale;
  msg.estop_active = fb.estop_active;
  msg.link_ok = fb.link_ok;
  return msg;
}

}  // namespace porter::scout_mini
