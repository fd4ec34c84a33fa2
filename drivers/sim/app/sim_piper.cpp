#include "sim_piper.hpp"

#include <cmath>

namespace porter::sim {

std::optional<piper::FeedbackStream> SimulatedPiper::stream_of(std::uint32_t id) {
  using piper::FeedbackStream;
  namespace pid = piper::id;
  if (id == pid::kArmStatus) return FeedbackStream::status;
  if (id >= pid::kEndPose1 && id <= pid::kEndPose3) return FeedbackStream::end_pose;
  if (id >= pid::kJointFeedback12 && id <= pid::kJointFeedback56) return FeedbackStream::joint_angles;
  if (id == pid::kGripperFeedback) return FeedbackStream::gripper;
  if (id >= pid::kHighSpeed1 && id < pid::kHighSpeed1 + piper::kNumJoints) return FeedbackStream::high_speed;
  if (id >= pid::kLowSpeed1 && id < pid::kLowSpeed1 + piper::kNumJoints) return FeedbackStream::low_speed;
  return std::nullopt;
}

void SimulatedPiper::advance(double t_s, std::vector<can::CanFrame>& out) {
  if (power_on_at_s_ >= 0.0 && t_s >= power_on_at_s_) {
    // Off until the boot time (the model is silent and holds its joints), then on.
    fw_.advance(power_on_at_s_, out);
    fw_.set_powered(true);
    power_on_at_s_ = -1.0;
  }
  fw_.advance(t_s, out);
}

bool SimulatedPiper::power_cycle(double t_s, double off_s) {
  if (!(off_s >= 0.0) || !std::isfinite(off_s)) return false;
  fw_.set_powered(false);
  power_on_at_s_ = t_s + off_s;
  return true;
}

bool SimulatedPiper::set_stream_enabled(std::uint32_t can_id, bool enabled) {
  const auto stream = stream_of(can_id);
  if (!stream) return false;
  fw_.set_stream_enabled(*stream, enabled);
  return true;
}

bool SimulatedPiper::raise_error(std::uint32_t code) {
  if (code == 0 || code > 0xFFFF) return false;
  fw_.inject_err_code(static_cast<std::uint16_t>(code));
  return true;
}

bool SimulatedPiper::clear_errors() {
  fw_.clear_injected_faults();
  return true;
}

}  // namespace porter::sim
