#pragma once
// PiperFirmware: a model of the Agilex Piper's controller as seen from its CAN bus, answering
// porter-arm byte for byte so the stack runs without the arm. porter-sim hosts it on the arm bus
// (a porter::can::SimulatedNode); tests drive it directly in simulated time.
//
// Behaviour:
// - Powers up disabled, in standby (ctrl_mode 0x00), MOVE P, speed 0 %, joints at
//   initial_q_rad, e-stop clear.
// - 0x471 enables (after enable_delay_s) or disables joints: motor 1..6 one joint, 7 every
//   joint, 0xFF every joint and the gripper. Disabling stops a joint where it is (brake).
// - 0x151 sets ctrl_mode, move mode and speed %. Entering CAN mode resets targets to the
//   current position.
// - 0x155..0x157 are obeyed only while every joint is enabled, ctrl_mode is CAN, the move mode
//   is MOVE J and no e-stop is active; otherwise ignored (counted). A target outside
//   [lower_rad, upper_rad] is clamped and sets that joint's angle-limit bit in the 0x2A1
//   err_code and arm status 0x04 until an in-range target for that joint arrives.
// - Joints move toward their targets at most max_speed_radps · speed % / 100, accelerating at
//   most max_accel_radps2 (a trapezoid profile, stepped every 1 ms on a fixed grid).
// - 0x150 stop: every joint decelerates to rest and targets are ignored, arm status 0x01;
//   resume: e-stop clear and ctrl_mode back to standby, so the host must send 0x151 again.
// - 0x159 enables / disables the gripper and sets its target stroke (clamped to
//   [0, gripper_max_m]), which it approaches at gripper_speed_mps; 0xAE sets the "zeroed" bit.
// - Feedback on a 5 ms grid: 0x2A1, 0x2A2..0x2A4 (flange pose from the DH table, piper_dh.hpp),
//   0x2A5..0x2A7, 0x2A8 and 0x251..0x256 every 5 ms (200 Hz); 0x261..0x266 every 25 ms (40 Hz).
//   Frames carry utime = their simulated send time in µs.
//
// Not modelled (reported as zero): motor and bus currents, so joint torques and gripper effort;
// gravity, payload and collisions. Temperatures and voltages are constant (30 / 35 °C, 24.0 V).
// Unverified against hardware: the enable delay, the reaction to an out-of-range target
// (clamp + flag; the firmware may refuse the target instead), standby after e-stop resume,
// brake-like hold when disabled (the real J2/J3 may sag), the 0x251.. position unit
// (sent here as 0.001 rad), and the 3 rad/s maximum joint speed (the 0x474 range).
//
// Fault hooks for tests: stop a feedback stream, raise error codes and status bits, power off /
// on / cycle (comes back disabled and in standby; joints stay where they are).
//
// Thread-safety: none; one thread drives the model (SimulatedNode contract).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "porter/can/simulated_node.hpp"
#include "porter/piper/protocol.hpp"

namespace porter::piper {

struct PiperFirmwareParams {
  using Joints = std::array<double, kNumJoints>;
  /// Firmware joint limits, rad. Default: the SDK's table (piper_param_manager.py). Agilex's own
  /// URDF disagrees on J4 (±1.832) and J6 (±3.14); Porter's URDF uses the SDK values.
  Joints lower_rad{-2.6179, 0.0, -2.967, -1.745, -1.22, -2.09439};
  Joints upper_rad{2.6179, 3.14, 0.0, 1.745, 1.22, 2.09439};
  /// Joint speed at 100 %, rad/s (0x474 accepts 0..3 rad/s).
  Joints max_speed_radps{3.0, 3.0, 3.0, 3.0, 3.0, 3.0};
  /// Joint acceleration bound, rad/s^2 (model choice).
  Joints max_accel_radps2{10.0, 10.0, 10.0, 10.0, 10.0, 10.0};
  Joints initial_q_rad{};
  double gripper_max_m = 0.07;
  double gripper_speed_mps = 0.05;
  double initial_gripper_m = 0.0;
  double enable_delay_s = 0.02;
};

/// The model's ground truth, for the simulated world and for tests.
struct PiperTruth {
  std::array<double, kNumJoints> q_rad{};      ///< robot-model joint angles (= SDK angles), rad
  std::array<double, kNumJoints> qd_radps{};
  std::array<double, kNumJoints> target_rad{};
  std::array<bool, kNumJoints> joint_enabled{};
  double gripper_m = 0.0;                      ///< gripper opening, m
  double gripper_target_m = 0.0;
  bool gripper_enabled = false;
  bool powered = true;
  bool estop = false;
  std::uint8_t ctrl_mode = 0;
  std::uint8_t move_mode = 0;
  std::uint8_t speed_pct = 0;
  std::uint16_t limit_bits = 0;                ///< err_code angle-limit bits the model raised
};

enum class FeedbackStream { status, end_pose, joint_angles, gripper, high_speed, low_speed };

struct PiperFirmwareCounters {
  std::uint64_t frames_received = 0;
  std::uint64_t frames_rejected = 0;   ///< command IDs that failed to decode
  std::uint64_t targets_ignored = 0;   ///< joint-target frames outside CAN + enabled + MOVE J
  std::uint64_t frames_sent = 0;
};

class PiperFirmware final : public can::SimulatedNode {
 public:
  explicit PiperFirmware(const PiperFirmwareParams& params = {});

  void receive(const can::CanFrame& frame, double t_s) override;
  void advance(double t_s, std::vector<can::CanFrame>& out) override;
  std::string name() const override { return "piper"; }

  const PiperTruth& truth() const { return truth_; }
  const PiperFirmwareCounters& counters() const { return counters_; }
  double time_s() const { return static_cast<double>(tick_) * kTickS; }

  // ---- fault hooks --------------------------------------------------------------------------
  void set_stream_enabled(FeedbackStream stream, bool enabled);
  /// Bits ORed into the reported 0x2A1 err_code until clear_injected_faults().
  void inject_err_code(std::uint16_t bits) { injected_err_ |= bits; }
  /// Reported as 0x2A1 arm status instead of the model's own (0 = none).
  void inject_arm_status(std::uint8_t status) { injected_arm_status_ = status; }
  /// Bits ORed into joint `joint` (0-based)'s 0x26x status byte.
  void inject_driver_status(int joint, std::uint8_t bits);
  void inject_gripper_status(std::uint8_t bits) { injected_gripper_ |= bits; }
  void clear_injected_faults();
  /// Power off (silent, deaf, joints held) or on (disabled, standby, MOVE P, e-stop clear).
  void set_powered(bool on);
  void power_cycle() {
    set_powered(false);
    set_powered(true);
  }

 private:
  static constexpr double kTickS = 0.001;
  void step_physics();
  void emit_feedback(std::int64_t tick, std::vector<can::CanFrame>& out);
  bool all_enabled() const;
  void hold_targets();

  PiperFirmwareParams p_;
  PiperTruth truth_;
  PiperFirmwareCounters counters_;
  std::int64_t tick_ = 0;  ///< physics state is at time tick_ * kTickS
  std::array<double, kNumJoints> enable_at_s_{};  ///< pending enable time, < 0 = none
  std::array<bool, 6> streams_{true, true, true, true, true, true};
  std::uint16_t injected_err_ = 0;
  std::uint8_t injected_arm_status_ = 0;
  std::array<std::uint8_t, kNumJoints> injected_driver_{};
  std::uint8_t injected_gripper_ = 0;
  bool gripper_zeroed_ = false;
  double gripper_effort_nm_ = 0.0;
};

}  // namespace porter::piper
