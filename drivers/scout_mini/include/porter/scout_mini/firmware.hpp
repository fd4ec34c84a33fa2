#pragma once
// A model of the Scout Mini's firmware as seen from its CAN bus (protocol V2), for porter-sim
// and tests: it answers porter-base byte for byte.
//
// Behaviour (protocol.hpp has the layouts and sources):
// - Powers up in standby: only 0x421 is obeyed. 0x421 B0 = 1 enters CAN command mode (0 back
//   to standby, 2 serial mode: CAN motion commands ignored).
// - In CAN mode, 0x111 sets the target (v, omega), saturated to the firmware limits (3.0 m/s,
//   2.5235 rad/s: ugv_sdk ScoutMiniLimits). With no 0x111 for command_timeout_s (500 ms) the
//   target is zero. 0x441 clears errors.
// - The body follows the target through a first-order lag (time_constant_s) whose rate is
//   bounded by the acceleration limits; within the settle band of the target it is on the
//   target (a motor controller settles; a pure exponential never reaches zero).
// - Raised faults (error_bit::kFaults) put the vehicle in the exception state and the target to
//   zero until cleared; warnings are only reported. The e-stop button (set_estop_button) does
//   the same with vehicle state e-stop.
// - Sends, at their real periods: 0x211 every 100 ms, 0x221, 0x251..0x254, 0x261..0x264 and
//   0x311 every 20 ms (manual v1.3.0 tables 3.1-3.8), 0x361 every 500 ms (period not in the
//   sources: an assumption). Every stream starts one period after power-on.
// - Integrates the base pose in the world (exact arcs per physics step) and the wheel travel.
//
// Modelling choices the sources do not settle (unverified, change them in FirmwareParams):
// motors 1..4 are front-right, front-left, rear-left, rear-right, so 0x251/0x254 report the
// right side; rpm is positive when the wheel drives the base forward; motor rpm = wheel rpm x
// gear_ratio; pulse count = motor revolutions x pulses_per_motor_rev; motor current is
// idle_current_a plus accel_current_a_per_mps2 per m/s^2 of that side's acceleration.
//
// Frame stamps: utime = simulated time in µs (SimulatedNode contract).
// Memory: frames received but not yet processed are bounded (input_queue_capacity, oldest
// dropped and counted), so a flood of bus bytes cannot grow the model.
// Thread-safety: none (one thread drives the node).

#include <array>
#include <cstdint>
#include <deque>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "porter/can/simulated_node.hpp"
#include "porter/scout_mini/protocol.hpp"

namespace porter::scout_mini {

struct FirmwareParams {
  double track_width_m = 0.4165;        ///< effective track of the diff-drive model
  double wheel_radius_m = 0.0875;       ///< effective wheel radius (rpm, pulses)
  double gear_ratio = 1.0;              ///< motor revolutions per wheel revolution (unverified)
  double pulses_per_motor_rev = 4096.0; ///< encoder pulses per motor revolution (unverified)
  double v_max_mps = 3.0;               ///< firmware saturation of the 0x111 linear speed
  double omega_max_radps = 2.5235;      ///< firmware saturation of the 0x111 yaw rate
  double linear_accel_max_mps2 = 1.5;   ///< bound on |dv/dt|
  double angular_accel_max_radps2 = 4.0;///< bound on |domega/dt|
  double time_constant_s = 0.05;        ///< first-order lag toward the target
  double settle_mps = 0.002;            ///< |target - v| below this: v = target
  double settle_radps = 0.002;          ///< same for omega
  double command_timeout_s = 0.5;       ///< no 0x111 for this long: target zero
  double battery_voltage_v = 25.2;      ///< reported in 0x211 and 0x261
  double idle_current_a = 0.3;
  double accel_current_a_per_mps2 = 2.0;
  double driver_temperature_c = 32.0;
  double motor_temperature_c = 30.0;
  double battery_soc_pct = 90.0;
  double physics_step_s = 0.001;        ///< largest integration step
  double system_state_period_s = 0.1;
  double motion_state_period_s = 0.02;
  double actuator_period_s = 0.02;      ///< 0x251..0x254 and 0x261..0x264
  double odometry_period_s = 0.02;
  double bms_period_s = 0.5;
  std::size_t input_queue_capacity = 4096;
};

/// Pose of the base frame B in the world: origin position and heading of x_B.
struct PlanarPose {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

class ScoutMiniFirmware final : public can::SimulatedNode {
 public:
  explicit ScoutMiniFirmware(FirmwareParams params = {}, PlanarPose initial_pose = {});

  // SimulatedNode
  void receive(const CanFrame& frame, double t_s) override;
  void advance(double t_s, std::vector<CanFrame>& out) override;
  std::string name() const override { return "scout_mini"; }
  bool power_cycle(double t_s, double off_s) override;
  bool set_stream_enabled(std::uint32_t can_id, bool enabled) override;
  bool raise_error(std::uint32_t code) override;
  bool clear_errors() override;

  /// The physical e-stop button: pressed = vehicle state e-stop, target zero.
  void set_estop_button(bool pressed) { estop_button_ = pressed; }
  /// Moves the body (a test or the simulator placing the robot); keeps velocities.
  void set_pose(const PlanarPose& pose) { pose_ = pose; }

  // Ground truth, at the time of the last advance().
  const PlanarPose& pose() const { return pose_; }
  double v_mps() const { return v_mps_; }
  double omega_radps() const { return omega_radps_; }
  double wheel_left_m() const { return left_m_; }   ///< travel since power-on
  double wheel_right_m() const { return right_m_; }
  ControlMode mode() const { return mode_; }
  bool powered() const { return powered_; }
  std::uint16_t errors() const { return errors_; }
  VehicleState vehicle_state() const;
  double time_s() const { return t_s_; }
  /// The target the body follows now (after mode, timeout, faults and saturation).
  MotionCommand target() const;

  /// Frames received while powered, frames ignored (wrong mode, unknown ID, undecodable) and
  /// frames dropped from a full input queue.
  std::uint64_t frames_received() const { return received_; }
  std::uint64_t frames_ignored() const { return ignored_; }
  std::uint64_t frames_dropped() const { return dropped_; }

 private:
  // A periodic stream sends at origin + k * period (k = 1, 2, ...): an integer grid, so the
  // send times do not drift with rounding.
  struct Stream {
    std::uint32_t first_id;
    int count;
    double period_s;
    std::array<bool, kNumMotors> enabled;
    double origin_s = 0.0;
    long index = 1;
    double next_s() const {
      return period_s > 0 ? origin_s + static_cast<double>(index) * period_s
                          : std::numeric_limits<double>::infinity();
    }
  };

  void process(const CanFrame& frame, double t_s);
  void integrate(double until_s);
  void step(double dt_s);
  void emit(Stream& stream, std::vector<CanFrame>& out);
  void boot(double t_s);
  double next_event(double limit_s) const;

  FirmwareParams params_;
  PlanarPose pose_;
  double t_s_ = 0.0;
  bool powered_ = true;
  double power_on_at_s_ = 0.0;
  ControlMode mode_ = ControlMode::standby;
  std::uint16_t errors_ = 0;
  bool estop_button_ = false;
  MotionCommand command_;
  double last_command_s_ = -1e300;
  double v_mps_ = 0.0;
  double omega_radps_ = 0.0;
  double accel_left_mps2_ = 0.0;
  double accel_right_mps2_ = 0.0;
  double left_m_ = 0.0;
  double right_m_ = 0.0;
  std::uint8_t system_count_ = 0;
  std::vector<Stream> streams_;
  std::deque<std::pair<double, CanFrame>> inputs_;
  std::uint64_t received_ = 0;
  std::uint64_t ignored_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace porter::scout_mini
