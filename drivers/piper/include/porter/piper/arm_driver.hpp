#pragma once
// The Piper driver's logic, free of I/O: frames and commands in, frames out, time passed in.
// porter-arm steps it from its loop; tests step it in simulated time against the firmware model.
//
//   ArmDriver driver(params);
//   driver.on_frame(frame, t_s);          // every frame received from the arm bus
//   driver.on_command(cmd, t_s);          // every ARM_CMD (t_s = receive time)
//   driver.on_estop(true, "operator: button", t_s);
//   driver.step(t_s, out);                // frames to send now are appended to `out`
//   driver.status(t_s); driver.feedback(); driver.take_events();
//
// Behaviour:
// - Enable sequence: 0x471 enable (motor 7) repeated every retry_period_s until every joint's
//   low-speed frame (0x261..0x266, bit 6) reports enabled; then 0x151 (CAN, MOVE J, speed)
//   repeated until 0x2A1 reports CAN mode and MOVE J; then active. Re-run whenever the arm
//   reports standby or a disabled joint (e.g. after a power cycle), and after the link returns.
// - Active: streams 0x155..0x157 every step: the newest command's targets clamped to
//   [lower_rad, upper_rad], or, when the command is stale (older than cmd_timeout_s), absent or
//   has enabled = false, the measured position latched at that moment (hold). 0x151 is sent
//   again when the commanded speed changes. 0x159 follows fresh commands that carry a gripper.
// - ESTOP: 0x150 stop at once and repeated until the arm reports e-stop; no targets; held until
//   on_estop(false). Then 0x150 resume until the arm leaves e-stop, the enable sequence, and a
//   hold until a command newer than the release arrives.
// - Shutdown: 0x471 disable (motor 0xFF) repeated until every joint reports disabled or
//   shutdown_timeout_s passed; then finished().
// - Faults (status().faults): arm status, err_code bits, motor and gripper fault bits by name,
//   plus "no_link" and "motor_feedback_stale".
//
// Time: t_s is any monotonic clock in seconds, non-decreasing across calls.
// Failure: nothing throws; malformed frames are counted (counters()) and reported once per ID
// as an event; on_command() refuses non-finite values. Memory is bounded whatever arrives.
// Thread-safety: none; one thread drives a driver.

#include <cstdint>
#include <string>
#include <vector>

#include "porter/can/can_frame.hpp"
#include "porter/piper/arm_driver_types.hpp"

namespace porter::piper {

class ArmDriver {
 public:
  explicit ArmDriver(const ArmDriverParams& params);

  void on_frame(const can::CanFrame& frame, double t_s);
  /// Returns false (and ignores the command) when a value is not finite.
  bool on_command(const ArmCommand& cmd, double t_s);
  /// `cause` names who and why, for the log ("operator: test").
  void on_estop(bool active, const std::string& cause, double t_s);
  /// Starts the clean shutdown (disable); step() keeps running it until finished().
  void request_shutdown(const std::string& cause, double t_s);
  void step(double t_s, std::vector<can::CanFrame>& out);

  bool finished() const { return phase_ == ArmPhase::off; }
  ArmPhase phase() const { return phase_; }
  ArmDriverStatus status(double t_s) const;
  const ArmFeedback& feedback() const { return fb_; }
  const ArmDriverCounters& counters() const { return counters_; }
  /// Speed % last sent in 0x151 (0 before any).
  int sent_speed_pct() const { return sent_speed_pct_; }
  /// Targets sent in the last active step, rad.
  const JointArray& last_targets() const { return last_targets_; }
  /// State changes since the last call, oldest first (at most 256 are kept).
  std::vector<ArmEvent> take_events();

 private:
  void set_phase(ArmPhase next, const std::string& cause, double t_s);
  void event(ArmEvent::Level level, std::string text);
  bool link_ok(double t_s) const;
  bool all_enabled_since(double since_s) const;
  bool all_disabled_since(double since_s) const;
  bool status_since(double since_s) const { return fb_.have_status && status_t_ > since_s; }
  bool command_fresh(double t_s) const;
  void step_active(double t_s, std::vector<can::CanFrame>& out);
  void step_shutdown(double t_s, std::vector<can::CanFrame>& out);
  void emit(can::CanFrame frame, std::vector<can::CanFrame>& out);
  void note_malformed(const can::CanFrame& frame, const char* why);
  void update_fault_events(double t_s);
  int desired_speed_pct(double t_s) const;

  ArmDriverParams p_;
  ArmFeedback fb_;
  ArmDriverCounters counters_;
  ArmPhase phase_ = ArmPhase::no_link;
  double phase_t_ = 0.0;
  double next_send_t_ = 0.0;
  double last_t_ = 0.0;
  std::string shutdown_cause_;
  double shutdown_t_ = 0.0;

  // Receive times (-1 = never).
  double status_t_ = -1.0;
  std::array<double, 3> joint_pair_t_{-1.0, -1.0, -1.0};
  std::array<double, kNumJoints> high_t_{};
  std::array<double, kNumJoints> low_t_{};
  bool link_was_ok_ = false;
  double link_up_t_ = -1.0;  ///< when the link last came up, -1 = never

  ArmCommand cmd_;
  double cmd_t_ = -1.0;
  double fresh_after_t_ = -1.0;
  bool estop_requested_ = false;
  bool estop_commanded_ = false;  ///< porter-arm put the arm in e-stop and must resume it

  enum class Hold { none, streaming, stale, disabled_cmd };
  Hold hold_state_ = Hold::none;
  JointArray hold_q_{};
  JointArray last_targets_{};
  bool clamping_ = false;
  int sent_speed_pct_ = 0;
  double mode_sent_t_ = -1.0;

  std::vector<std::uint32_t> malformed_logged_;
  std::string last_faults_;
  std::vector<ArmEvent> events_;
};

}  // namespace porter::piper
