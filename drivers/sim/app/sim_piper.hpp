#pragma once
// The Piper firmware model (porter::piper::PiperFirmware) as porter-sim hosts it: the model on
// the arm bus with the simulator's four fault hooks mapped onto the model's own.
//
//   power_cycle(t, off_s)          the arm is off (silent, deaf, joints held) from t for off_s,
//                                  then boots disabled and in standby (porter-arm re-enables it)
//   set_stream_enabled(id, on)     0x2A1 status; 0x2A2..0x2A4 end pose; 0x2A5..0x2A7 joint
//                                  angles; 0x2A8 gripper; 0x251..0x256 high-speed and
//                                  0x261..0x266 low-speed motor feedback. Any ID of a group
//                                  stops (or resumes) the whole group, as the model sends them
//                                  together.
//   raise_error(code)              code (1..0xFFFF) ORed into the 0x2A1 error word
//   clear_errors()                 clears raised error bits and injected statuses
//
// Thread-safety: none; the simulation thread drives it (SimulatedNode contract).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "porter/can/simulated_node.hpp"
#include "porter/piper/piper_firmware.hpp"

namespace porter::sim {

class SimulatedPiper final : public can::SimulatedNode {
 public:
  explicit SimulatedPiper(const piper::PiperFirmwareParams& params) : fw_(params) {}

  void receive(const can::CanFrame& frame, double t_s) override { fw_.receive(frame, t_s); }
  void advance(double t_s, std::vector<can::CanFrame>& out) override;
  std::string name() const override { return fw_.name(); }

  bool power_cycle(double t_s, double off_s) override;
  bool set_stream_enabled(std::uint32_t can_id, bool enabled) override;
  bool raise_error(std::uint32_t code) override;
  bool clear_errors() override;

  const piper::PiperFirmware& firmware() const { return fw_; }

  /// The feedback group of a CAN ID, or nothing when the arm sends no such frame.
  static std::optional<piper::FeedbackStream> stream_of(std::uint32_t can_id);

 private:
  piper::PiperFirmware fw_;
  double power_on_at_s_ = -1.0;  ///< pending boot time while off, < 0 = none
};

}  // namespace porter::sim
