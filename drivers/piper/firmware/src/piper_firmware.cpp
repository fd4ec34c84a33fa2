#include "porter/piper/piper_firmware.hpp"

#include <algorithm>
#include <cmath>

#include "porter/piper/commands.hpp"
#include "porter/piper/feedback.hpp"
#include "porter/piper/piper_dh.hpp"

namespace porter::piper {
namespace {

constexpr std::int64_t kHighRateTicks = 5;   // 200 Hz on the 1 ms grid
constexpr std::int64_t kLowRateTicks = 25;   // 40 Hz
constexpr double kReachedRad = 0.5 / kMilliDegPerRad;  // half a millidegree

std::int16_t sat16(double v) {
  const std::int32_t r = round_saturate_i32(v);
  return static_cast<std::int16_t>(std::clamp<std::int32_t>(r, -32768, 32767));
}

}  // namespace

PiperFirmware::PiperFirmware(const PiperFirmwareParams& params) : p_(params) {
  truth_.q_rad = p_.initial_q_rad;
  truth_.target_rad = p_.initial_q_rad;
  truth_.gripper_m = std::clamp(p_.initial_gripper_m, 0.0, p_.gripper_max_m);
  truth_.gripper_target_m = truth_.gripper_m;
  enable_at_s_.fill(-1.0);
}

bool PiperFirmware::all_enabled() const {
  return std::all_of(truth_.joint_enabled.begin(), truth_.joint_enabled.end(), [](bool e) { return e; });
}

void PiperFirmware::hold_targets() { truth_.target_rad = truth_.q_rad; }

void PiperFirmware::set_stream_enabled(FeedbackStream stream, bool enabled) {
  streams_[static_cast<std::size_t>(stream)] = enabled;
}

void PiperFirmware::inject_driver_status(int joint, std::uint8_t bits) {
  if (joint >= 0 && joint < kNumJoints) injected_driver_[joint] |= bits;
}

void PiperFirmware::clear_injected_faults() {
  injected_err_ = 0;
  injected_arm_status_ = 0;
  injected_driver_.fill(0);
  injected_gripper_ = 0;
}

void PiperFirmware::set_powered(bool on) {
  if (on == truth_.powered) return;
  truth_.powered = on;
  truth_.qd_radps.fill(0.0);
  truth_.joint_enabled.fill(false);
  enable_at_s_.fill(-1.0);
  truth_.gripper_enabled = false;
  truth_.gripper_target_m = truth_.gripper_m;
  hold_targets();
  if (on) {
    truth_.ctrl_mode = ctrl_mode::kStandby;
    truth_.move_mode = move_mode::kMoveP;
    truth_.speed_pct = 0;
    truth_.estop = false;
    truth_.limit_bits = 0;
  }
}

void PiperFirmware::receive(const can::CanFrame& f, double t_s) {
  ++counters_.frames_received;
  if (!truth_.powered || f.extended || f.rtr) return;
  DecodeStatus s = DecodeStatus::ok;
  switch (f.id) {
    case id::kMotorEnable: {
      EnableCommand e;
      if ((s = decode_enable(f, e)) != DecodeStatus::ok) break;
      const int first = e.motor >= 1 && e.motor <= kNumJoints ? e.motor - 1 : 0;
      const int last = e.motor >= 1 && e.motor <= kNumJoints ? e.motor - 1 : kNumJoints - 1;
      for (int j = first; j <= last; ++j) {
        if (e.enable) {
          if (!truth_.joint_enabled[j] && enable_at_s_[j] < 0.0) enable_at_s_[j] = t_s + p_.enable_delay_s;
        } else {
          truth_.joint_enabled[j] = false;
          enable_at_s_[j] = -1.0;
          truth_.qd_radps[j] = 0.0;
          truth_.target_rad[j] = truth_.q_rad[j];
        }
      }
      if (e.motor == kMotorAll) {
        truth_.gripper_enabled = e.enable;
        truth_.gripper_target_m = truth_.gripper_m;
      }
      break;
    }
    case id::kMotionCtrl2: {
      ModeCommand m;
      if ((s = decode_mode(f, m)) != DecodeStatus::ok) break;
      if (m.ctrl_mode == ctrl_mode::kCan && truth_.ctrl_mode != ctrl_mode::kCan) hold_targets();
      truth_.ctrl_mode = m.ctrl_mode;
      truth_.move_mode = m.move_mode;
      truth_.speed_pct = m.speed_pct;
      break;
    }
    case id::kMotionCtrl1: {
      MotionCommand m;
      if ((s = decode_motion(f, m)) != DecodeStatus::ok) break;
      if (m.estop == estop_action::kStop) {
        truth_.estop = true;
      } else if (m.estop == estop_action::kResume && truth_.estop) {
        truth_.estop = false;
        truth_.ctrl_mode = ctrl_mode::kStandby;
        hold_targets();
      }
      break;
    }
    case id::kJointCtrl12:
    case id::kJointCtrl34:
    case id::kJointCtrl56: {
      JointPair pair;
      if ((s = decode_joint_target_pair(f, pair)) != DecodeStatus::ok) break;
      if (!all_enabled() || truth_.ctrl_mode != ctrl_mode::kCan || truth_.move_mode != move_mode::kMoveJ ||
          truth_.estop) {
        ++counters_.targets_ignored;
        break;
      }
      for (int k = 0; k < 2; ++k) {
        const int j = pair.first + k;
        const double q = mdeg_to_rad(pair.mdeg[k]);
        const std::uint16_t bit = err_angle_limit_bit(j);
        if (q < p_.lower_rad[j] || q > p_.upper_rad[j]) {
          truth_.limit_bits |= bit;
        } else {
          truth_.limit_bits &= static_cast<std::uint16_t>(~bit);
        }
        truth_.target_rad[j] = std::clamp(q, p_.lower_rad[j], p_.upper_rad[j]);
      }
      break;
    }
    case id::kGripperCtrl: {
      GripperCommand g;
      if ((s = decode_gripper(f, g)) != DecodeStatus::ok) break;
      const bool enable = g.code == gripper_code::kEnable || g.code == gripper_code::kEnableClearError;
      if (g.code == gripper_code::kDisableClearError || g.code == gripper_code::kEnableClearError) {
        injected_gripper_ = 0;
      }
      truth_.gripper_enabled = enable;
      if (enable) {
        truth_.gripper_target_m = std::clamp(static_cast<double>(g.stroke_um) * 1e-6, 0.0, p_.gripper_max_m);
        gripper_effort_nm_ = g.effort_mnm * 1e-3;
      } else {
        truth_.gripper_target_m = truth_.gripper_m;
      }
      if (g.set_zero) gripper_zeroed_ = true;
      break;
    }
    default:
      return;  // feedback of other nodes, unsupported commands
  }
  if (s != DecodeStatus::ok) ++counters_.frames_rejected;
}

void PiperFirmware::step_physics() {
  const double t = static_cast<double>(tick_) * kTickS;
  for (int j = 0; j < kNumJoints; ++j) {
    if (enable_at_s_[j] >= 0.0 && t >= enable_at_s_[j]) {
      truth_.joint_enabled[j] = true;
      enable_at_s_[j] = -1.0;
      truth_.target_rad[j] = truth_.q_rad[j];
    }
  }
  if (!truth_.powered) return;
  const double dt = kTickS;
  for (int j = 0; j < kNumJoints; ++j) {
    double& q = truth_.q_rad[j];
    double& v = truth_.qd_radps[j];
    if (!truth_.joint_enabled[j]) {
      v = 0.0;
      continue;
    }
    const double a = p_.max_accel_radps2[j];
    double v_des = 0.0;
    if (!truth_.estop) {
      const double v_max = p_.max_speed_radps[j] * truth_.speed_pct / 100.0;
      const double d = truth_.target_rad[j] - q;
      // Fastest speed from which the joint can still stop at the target.
      v_des = std::copysign(std::min(v_max, std::sqrt(2.0 * a * std::abs(d))), d);
    }
    const double v_new = std::clamp(v_des, v - a * dt, v + a * dt);
    const double q_new = q + 0.5 * (v + v_new) * dt;
    const double before = truth_.target_rad[j] - q;
    const double after = truth_.target_rad[j] - q_new;
    if (!truth_.estop && before != 0.0 && (after == 0.0 || std::signbit(after) != std::signbit(before))) {
      q = truth_.target_rad[j];  // arrived within this step
      v = 0.0;
    } else {
      q = q_new;
      v = v_new;
    }
    // The hard stops: braking from full speed toward a target at a limit may not overshoot it.
    if (q < p_.lower_rad[j] || q > p_.upper_rad[j]) {
      q = std::clamp(q, p_.lower_rad[j], p_.upper_rad[j]);
      v = 0.0;
    }
  }
  if (truth_.gripper_enabled) {
    const double d = truth_.gripper_target_m - truth_.gripper_m;
    const double step = p_.gripper_speed_mps * dt;
    truth_.gripper_m = std::abs(d) <= step ? truth_.gripper_target_m : truth_.gripper_m + std::copysign(step, d);
  }
}

void PiperFirmware::advance(double t_s, std::vector<can::CanFrame>& out) {
  const auto last = static_cast<std::int64_t>(std::floor(t_s / kTickS + 1e-9));
  while (tick_ < last) {
    ++tick_;
    step_physics();
    if (truth_.powered) emit_feedback(tick_, out);
  }
}

void PiperFirmware::emit_feedback(std::int64_t tick, std::vector<can::CanFrame>& out) {
  if (tick % kHighRateTicks != 0) return;
  const std::int64_t utime = tick * 1000;  // 1 ms ticks
  const std::size_t first = out.size();
  auto on = [&](FeedbackStream s) { return streams_[static_cast<std::size_t>(s)]; };

  if (on(FeedbackStream::status)) {
    StatusFeedback st;
    st.ctrl_mode = truth_.ctrl_mode;
    st.move_mode = truth_.move_mode;
    st.err_code = static_cast<std::uint16_t>(truth_.limit_bits | injected_err_);
    if (injected_arm_status_ != 0) st.arm_status = injected_arm_status_;
    else if (truth_.estop) st.arm_status = arm_status::kEmergencyStop;
    else if (truth_.limit_bits != 0) st.arm_status = arm_status::kTargetExceedsLimit;
    for (int j = 0; j < kNumJoints; ++j) {
      if (std::abs(truth_.target_rad[j] - truth_.q_rad[j]) > kReachedRad) st.motion_status = 1;
    }
    out.push_back(encode_status(st));
  }
  if (on(FeedbackStream::end_pose)) {
    const FlangePose pose = piper_flange_pose(truth_.q_rad);
    const std::array<std::int32_t, 6> v = {
        round_saturate_i32(pose.p_m[0] * 1e6),        round_saturate_i32(pose.p_m[1] * 1e6),
        round_saturate_i32(pose.p_m[2] * 1e6),        rad_to_mdeg(pose.rpy_rad[0]),
        rad_to_mdeg(pose.rpy_rad[1]),                 rad_to_mdeg(pose.rpy_rad[2])};
    for (int i = 0; i < 3; ++i) out.push_back(encode_end_pose_pair({i, {v[2 * i], v[2 * i + 1]}}));
  }
  if (on(FeedbackStream::joint_angles)) {
    for (int i = 0; i < 3; ++i) {
      out.push_back(encode_joint_angle_pair(
          {2 * i, {rad_to_mdeg(truth_.q_rad[2 * i]), rad_to_mdeg(truth_.q_rad[2 * i + 1])}}));
    }
  }
  if (on(FeedbackStream::gripper)) {
    GripperFeedback g;
    g.stroke_um = round_saturate_i32(truth_.gripper_m * 1e6);
    g.effort_mnm = 0;
    g.status = static_cast<std::uint8_t>((truth_.gripper_enabled ? kGripperStatusEnabled : 0) |
                                         (gripper_zeroed_ ? kGripperStatusZeroed : 0) | injected_gripper_);
    out.push_back(encode_gripper_feedback(g));
  }
  if (on(FeedbackStream::high_speed)) {
    for (int j = 0; j < kNumJoints; ++j) {
      HighSpeedFeedback h;
      h.joint = j;
      h.speed_mradps = sat16(truth_.qd_radps[j] * 1e3);
      h.current_ma = 0;
      h.position_raw = round_saturate_i32(truth_.q_rad[j] * 1e3);
      out.push_back(encode_high_speed(h));
    }
  }
  if (on(FeedbackStream::low_speed) && tick % kLowRateTicks == 0) {
    for (int j = 0; j < kNumJoints; ++j) {
      LowSpeedFeedback l;
      l.joint = j;
      l.voltage_dv = 240;
      l.driver_temp_c = 35;
      l.motor_temp_c = 30;
      l.status = static_cast<std::uint8_t>((truth_.joint_enabled[j] ? kDriverStatusEnabled : 0) |
                                           injected_driver_[j]);
      out.push_back(encode_low_speed(l));
    }
  }
  for (std::size_t i = first; i < out.size(); ++i) out[i].utime = utime;
  counters_.frames_sent += out.size() - first;
}

}  // namespace porter::piper
