#pragma once
// The Scout Mini driver's logic, free of I/O and clocks: porter-base feeds it CAN frames,
// BASE_CMD and ESTOP with their receive times (monotonic seconds) and sends what tick() returns
// at the command rate; tests step it against ScoutMiniFirmware in simulated time.
//
// What it does:
// - Command mode: until the base reports CAN command mode in 0x211 (at start, after a power
//   cycle the base is back in standby, or when something else switched it), 0x421 (CAN mode) is
//   sent every mode_retry_period_s.
// - 0x111 every tick. The velocity is the latest BASE_CMD, limited (see limit_command), or zero
//   when: there is none; it is disabled; it is stale; ESTOP is engaged (latched until an
//   explicit release, and then a BASE_CMD received after the release is needed); CAN feedback
//   is lost (the driver does not drive a base it cannot see); the base speaks protocol V1.
// - Staleness: a BASE_CMD drives the base for at most command_stale_s after it was received:
//   the 0x111 sent at tick t uses it only while t + command_period_s <= t_received +
//   command_stale_s (the base holds a 0x111 until the next one), so the zero 0x111 reaches the
//   base no later than command_stale_s after the last command, up to the tick's wake-up jitter.
// - Feedback: 0x211 (vehicle state, mode, battery, error bits as names), 0x221 (v, omega),
//   0x251..0x254, 0x261..0x264, 0x311 (odometry integrated from the wheel distances with the
//   configured track; a jump larger than odometry_jump_m, e.g. the counters restarting after a
//   power cycle, re-bases without moving the pose), 0x361 (battery SOC).
// - Protocol V1: a V1-only frame (0x151) before any V2 frame makes the driver refuse for good:
//   it sends nothing and reports the reason.
// - Every state change becomes a DriverEvent with its cause (take_events()); the process logs
//   them. Events are bounded (the oldest are dropped beyond 256 untaken).
//
// Failure: malformed frames are counted and skipped; nothing here throws, prints or allocates
// without bound, whatever the bus carries.
// Thread-safety: none; the caller serializes calls (porter-base holds a mutex).

#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "porter/scout_mini/protocol.hpp"

namespace porter::scout_mini {

struct DriverParams {
  double command_period_s = 0.02;       ///< tick period (0x111 at 50 Hz)
  double command_stale_s = 0.2;         ///< BASE_CMD lifetime (see header comment)
  double v_max_mps = 1.0;               ///< |v| limit sent
  double omega_max_radps = 2.5;         ///< |omega| limit sent
  double track_width_m = 0.4165;        ///< effective track: odometry and wheel limit
  double wheel_radius_m = 0.0875;       ///< effective wheel radius: wheel limit
  double wheel_omega_max_radps = 12.0;  ///< |v -+ omega * track / 2| <= this * radius
  double feedback_timeout_s = 0.25;     ///< no feedback frame for this long: link lost
  double mode_retry_period_s = 0.1;     ///< 0x421 repeat period until the base is in CAN mode
  double odometry_jump_m = 0.5;         ///< a 0x311 step above this is a counter reset
};

struct VelocityCommand {
  bool enabled = false;
  double v_mps = 0.0;
  double omega_radps = 0.0;
};

/// (v, omega) scaled by one common factor (so the path's curvature is kept) until |v|,
/// |omega| and both wheel speeds are within the limits; non-finite input gives zero.
/// `limited` tells whether the command was changed.
VelocityCommand limit_command(const VelocityCommand& command, const DriverParams& params,
                              bool* limited = nullptr);

enum class EventLevel { info, warn, error };

struct DriverEvent {
  double t_s = 0.0;
  EventLevel level = EventLevel::info;
  std::string message;
};

/// Everything porter-base publishes on BASE_STATE, decoded.
struct BaseFeedback {
  double v_mps = 0.0;
  double omega_radps = 0.0;
  double wheel_left_m = 0.0;   ///< cumulative since the driver started (across counter resets)
  double wheel_right_m = 0.0;
  double odom_x_m = 0.0;
  double odom_y_m = 0.0;
  double odom_yaw_rad = 0.0;
  std::array<double, kNumMotors> motor_speed_rpm{};
  std::array<double, kNumMotors> motor_current_a{};
  std::array<double, kNumMotors> driver_temperature_c{};
  std::array<double, kNumMotors> motor_temperature_c{};
  std::array<std::uint8_t, kNumMotors> driver_status{};
  double battery_voltage_v = 0.0;
  double battery_soc_pct = -1.0;  ///< -1 until 0x361 arrives
  int vehicle_state = -1;         ///< VehicleState value, -1 until 0x211 arrives
  int control_mode = -1;          ///< ControlMode value, -1 until 0x211 arrives
  std::uint16_t error_bits = 0;
  bool cmd_stale = true;
  bool estop_active = false;
  bool link_ok = false;
  bool refused_v1 = false;
  std::int64_t feedback_utime = 0;  ///< utime of the newest feedback frame (0 = none)
};

class BaseDriver {
 public:
  explicit BaseDriver(DriverParams params);

  void on_frame(const CanFrame& frame, double t_s);
  void on_command(const VelocityCommand& command, double t_s);
  void on_estop(bool active, const std::string& cause, double t_s);
  /// Frames to send at tick time t_s (0x421 when due, then 0x111), appended to `out`.
  void tick(double t_s, std::vector<CanFrame>& out);
  /// A zero 0x111 (clean shutdown); nothing when refused.
  void stop_frames(std::vector<CanFrame>& out) const;

  const BaseFeedback& feedback() const { return feedback_; }
  /// The velocity of the last 0x111 from tick().
  const VelocityCommand& last_sent() const { return last_sent_; }
  bool refused() const { return feedback_.refused_v1; }
  /// A one-line summary of what is wrong ("" when nothing): for the heartbeat.
  std::string problem() const;

  std::vector<DriverEvent> take_events();

  std::uint64_t frames_decoded() const { return decoded_; }
  std::uint64_t frames_malformed() const { return malformed_; }
  std::uint64_t frames_unknown() const { return unknown_; }
  std::uint64_t events_dropped() const { return events_dropped_; }

 private:
  void event(double t_s, EventLevel level, std::string message);
  void on_system_state(const SystemState& st, double t_s);
  void on_odometry(const Odometry& odo, double t_s);
  void update_link(double t_s);

  DriverParams params_;
  BaseFeedback feedback_;
  VelocityCommand command_;
  bool have_command_ = false;
  double command_t_s_ = -1e300;
  double estop_release_t_s_ = -1e300;
  double last_feedback_t_s_ = -1e300;
  double last_mode_sent_t_s_ = -1e300;
  double last_odometry_t_s_ = -1e300;
  bool seen_v2_ = false;
  bool v1_warned_ = false;
  bool link_ever_ok_ = false;
  bool have_odometry_ = false;
  Odometry last_odometry_;
  bool limited_ = false;
  VelocityCommand last_sent_;
  std::deque<DriverEvent> events_;
  std::uint64_t decoded_ = 0;
  std::uint64_t malformed_ = 0;
  std::uint64_t unknown_ = 0;
  std::uint64_t events_dropped_ = 0;
};

}  // namespace porter::scout_mini
