#include "porter/piper/arm_driver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "porter/piper/commands.hpp"
#include "porter/piper/faults.hpp"
#include "porter/piper/feedback.hpp"

namespace porter::piper {
namespace {

constexpr std::size_t kMaxEvents = 256;

std::string fmt(const char* format, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, a);
  return buf;
}

std::string ms(double seconds) { return fmt("%.0f ms", seconds * 1e3); }

bool all_finite(const JointArray& a) {
  return std::all_of(a.begin(), a.end(), [](double v) { return std::isfinite(v); });
}

}  // namespace

const char* to_string(ArmPhase phase) {
  switch (phase) {
    case ArmPhase::no_link: return "no_link";
    case ArmPhase::enabling: return "enabling";
    case ArmPhase::setting_mode: return "setting_mode";
    case ArmPhase::active: return "active";
    case ArmPhase::estop: return "estop";
    case ArmPhase::releasing: return "releasing";
    case ArmPhase::shutting_down: return "shutting_down";
    case ArmPhase::off: return "off";
  }
  return "unknown";
}

ArmDriver::ArmDriver(const ArmDriverParams& params) : p_(params) {
  high_t_.fill(-1.0);
  low_t_.fill(-1.0);
}

void ArmDriver::event(ArmEvent::Level level, std::string text) {
  if (events_.size() >= kMaxEvents) events_.erase(events_.begin());
  events_.push_back({level, std::move(text)});
}

std::vector<ArmEvent> ArmDriver::take_events() {
  std::vector<ArmEvent> out;
  out.swap(events_);
  return out;
}

void ArmDriver::set_phase(ArmPhase next, const std::string& cause, double t_s) {
  if (next == phase_) return;
  const ArmEvent::Level level =
      (next == ArmPhase::no_link || next == ArmPhase::estop) ? ArmEvent::Level::warn : ArmEvent::Level::info;
  event(level, std::string(to_string(phase_)) + " -> " + to_string(next) + ": " + cause);
  phase_ = next;
  phase_t_ = t_s;
  next_send_t_ = t_s;  // the phase's first frame goes out in this step
}

void ArmDriver::note_malformed(const can::CanFrame& frame, const char* why) {
  ++counters_.frames_malformed;
  if (std::find(malformed_logged_.begin(), malformed_logged_.end(), frame.id) != malformed_logged_.end()) return;
  if (malformed_logged_.size() < 64) malformed_logged_.push_back(frame.id);
  event(ArmEvent::Level::warn, "malformed frame " + can::to_string(frame) + ": " + why +
                                   " (further malformed frames with this ID are counted, not logged)");
}

void ArmDriver::on_frame(const can::CanFrame& f, double t_s) {
  ++counters_.frames_received;
  if (f.extended || f.rtr) {
    ++counters_.frames_ignored;
    return;
  }
  DecodeStatus s = DecodeStatus::ok;
  if (f.id == id::kArmStatus) {
    StatusFeedback st;
    if ((s = decode_status(f, st)) == DecodeStatus::ok) {
      fb_.have_status = true;
      fb_.ctrl_mode = st.ctrl_mode;
      fb_.arm_status = st.arm_status;
      fb_.move_mode = st.move_mode;
      fb_.motion_status = st.motion_status;
      fb_.err_code = st.err_code;
      status_t_ = t_s;
    }
  } else if (f.id >= id::kJointFeedback12 && f.id <= id::kJointFeedback56) {
    JointAnglePair jp;
    if ((s = decode_joint_angle_pair(f, jp)) == DecodeStatus::ok) {
      fb_.q_rad[jp.first] = mdeg_to_rad(jp.mdeg[0]);
      fb_.q_rad[jp.first + 1] = mdeg_to_rad(jp.mdeg[1]);
      joint_pair_t_[jp.first / 2] = t_s;
      fb_.joints_t_s = t_s;
      fb_.joints_frame_utime = f.utime;
    }
  } else if (f.id == id::kGripperFeedback) {
    GripperFeedback g;
    if ((s = decode_gripper_feedback(f, g)) == DecodeStatus::ok) {
      fb_.gripper_m = g.stroke_m();
      fb_.gripper_effort_nm = g.effort_nm();
      fb_.gripper_status = g.status;
    }
  } else if (f.id >= id::kHighSpeed1 && f.id < id::kHighSpeed1 + kNumJoints) {
    HighSpeedFeedback h;
    if ((s = decode_high_speed(f, h)) == DecodeStatus::ok) {
      fb_.qd_radps[h.joint] = h.speed_radps();
      fb_.effort_nm[h.joint] = h.current_a() * p_.torque_constant_nm_per_a[h.joint];
      high_t_[h.joint] = t_s;
    }
  } else if (f.id >= id::kLowSpeed1 && f.id < id::kLowSpeed1 + kNumJoints) {
    LowSpeedFeedback l;
    if ((s = decode_low_speed(f, l)) == DecodeStatus::ok) {
      fb_.bus_voltage_v[l.joint] = l.voltage_dv * 0.1;
      fb_.driver_temperature_c[l.joint] = l.driver_temp_c;
      fb_.motor_temperature_c[l.joint] = l.motor_temp_c;
      fb_.driver_status[l.joint] = l.status;
      fb_.joint_enabled[l.joint] = l.enabled();
      low_t_[l.joint] = t_s;
    }
  } else {
    ++counters_.frames_ignored;  // end pose, responses, other nodes' commands
    return;
  }
  if (s != DecodeStatus::ok) note_malformed(f, to_string(s));
}

bool ArmDriver::on_command(const ArmCommand& cmd, double t_s) {
  if (!all_finite(cmd.q_rad) || !std::isfinite(cmd.speed_pct) ||
      (cmd.has_gripper && (!std::isfinite(cmd.gripper_m) || !std::isfinite(cmd.gripper_effort_nm)))) {
    return false;
  }
  cmd_ = cmd;
  cmd_t_ = t_s;
  ++counters_.commands_accepted;
  return true;
}

void ArmDriver::on_estop(bool active, const std::string& cause, double t_s) {
  if (phase_ == ArmPhase::shutting_down || phase_ == ArmPhase::off) return;
  if (active && !estop_requested_) {
    estop_requested_ = true;
    set_phase(ArmPhase::estop, "ESTOP active (" + cause + ")", t_s);
  } else if (!active && estop_requested_) {
    estop_requested_ = false;
    fresh_after_t_ = t_s;
    set_phase(ArmPhase::releasing, "ESTOP released (" + cause + ")", t_s);
  }
}

void ArmDriver::request_shutdown(const std::string& cause, double t_s) {
  if (phase_ == ArmPhase::shutting_down || phase_ == ArmPhase::off) return;
  shutdown_cause_ = cause;
  shutdown_t_ = t_s;
  set_phase(ArmPhase::shutting_down, cause + ": disabling the arm", t_s);
}

bool ArmDriver::link_ok(double t_s) const {
  if (!fb_.have_status || t_s - status_t_ > p_.link_timeout_s) return false;
  for (double tj : joint_pair_t_) {
    if (tj < 0.0 || t_s - tj > p_.link_timeout_s) return false;
  }
  return true;
}

bool ArmDriver::all_enabled_since(double since_s) const {
  for (int j = 0; j < kNumJoints; ++j) {
    if (low_t_[j] <= since_s || !fb_.joint_enabled[j]) return false;
  }
  return true;
}

bool ArmDriver::all_disabled_since(double since_s) const {
  for (int j = 0; j < kNumJoints; ++j) {
    if (low_t_[j] <= since_s || fb_.joint_enabled[j]) return false;
  }
  return true;
}

bool ArmDriver::command_fresh(double t_s) const {
  return cmd_t_ >= 0.0 && cmd_t_ > fresh_after_t_ && t_s - cmd_t_ <= p_.cmd_timeout_s;
}

int ArmDriver::desired_speed_pct(double t_s) const {
  if (command_fresh(t_s) && cmd_.speed_pct > 0.0 && cmd_.speed_pct <= 100.0) {
    return std::clamp(static_cast<int>(std::lround(cmd_.speed_pct)), 1, 100);
  }
  return std::clamp(p_.default_speed_pct, 1, 100);
}

void ArmDriver::emit(can::CanFrame frame, std::vector<can::CanFrame>& out) {
  out.push_back(frame);
  ++counters_.frames_sent;
}

void ArmDriver::step(double t_s, std::vector<can::CanFrame>& out) {
  last_t_ = t_s;
  if (phase_ == ArmPhase::off) return;
  if (phase_ == ArmPhase::shutting_down) {
    step_shutdown(t_s, out);
    update_fault_events(t_s);
    return;
  }

  const bool link = link_ok(t_s);
  if (link != link_was_ok_) {
    if (link) {
      link_up_t_ = t_s;
      event(ArmEvent::Level::info, "link up: status and joint feedback arriving");
    } else if (fb_.have_status) {
      event(ArmEvent::Level::warn,
            "link down: newest 0x2A1 status " + ms(t_s - status_t_) + " old, joint feedback " +
                ms(t_s - *std::min_element(joint_pair_t_.begin(), joint_pair_t_.end())) + " old");
    }
    link_was_ok_ = link;
  }

  const bool due = t_s >= next_send_t_;
  auto sent_retry = [&] { next_send_t_ = t_s + p_.retry_period_s; };
  const bool arm_in_estop = fb_.have_status && fb_.arm_status == arm_status::kEmergencyStop;

  switch (phase_) {
    case ArmPhase::no_link:
      if (estop_requested_) {
        set_phase(ArmPhase::estop, "ESTOP active while the link is down", t_s);
      } else if (link) {
        set_phase(ArmPhase::enabling, "feedback arriving", t_s);
      }
      break;
    case ArmPhase::estop:
      // Repeat until the arm confirms (and again if it stops confirming, e.g. after a power cycle).
      if (t_s >= next_send_t_ && !(status_since(phase_t_) && arm_in_estop)) {
        MotionCommand m;
        m.estop = estop_action::kStop;
        emit(encode_motion(m), out);
        estop_commanded_ = true;
        sent_retry();
      }
      break;
    case ArmPhase::releasing:
      if (!link) {
        set_phase(ArmPhase::no_link, "link down while resuming from e-stop", t_s);
      } else if (status_since(phase_t_) && !arm_in_estop) {
        estop_commanded_ = false;
        set_phase(ArmPhase::enabling, "arm left e-stop", t_s);
      } else if (due) {
        MotionCommand m;
        m.estop = estop_action::kResume;
        emit(encode_motion(m), out);
        sent_retry();
      }
      break;
    case ArmPhase::enabling:
      if (!link) {
        set_phase(ArmPhase::no_link, "link down", t_s);
      } else if (arm_in_estop && estop_commanded_) {
        set_phase(ArmPhase::releasing, "arm still in the e-stop porter-arm sent", t_s);
      } else if (all_enabled_since(phase_t_)) {
        set_phase(ArmPhase::setting_mode, "every joint reports enabled", t_s);
      } else if (due) {
        emit(encode_enable({kMotorAllJoints, true}), out);
        sent_retry();
      }
      break;
    case ArmPhase::setting_mode: {
      if (!link) {
        set_phase(ArmPhase::no_link, "link down", t_s);
        break;
      }
      int disabled = -1;
      for (int j = 0; j < kNumJoints; ++j) {
        if (low_t_[j] > phase_t_ && !fb_.joint_enabled[j]) disabled = j;
      }
      if (disabled >= 0) {
        set_phase(ArmPhase::enabling, "joint" + std::to_string(disabled + 1) + " reports disabled", t_s);
      } else if (mode_sent_t_ >= phase_t_ && status_since(mode_sent_t_) &&
                 fb_.ctrl_mode == ctrl_mode::kCan && fb_.move_mode == move_mode::kMoveJ) {
        hold_q_ = fb_.q_rad;
        hold_state_ = Hold::none;
        set_phase(ArmPhase::active, "arm reports CAN control, MOVE J", t_s);
        step_active(t_s, out);
      } else if (due) {
        ModeCommand m;
        m.speed_pct = static_cast<std::uint8_t>(desired_speed_pct(t_s));
        emit(encode_mode(m), out);
        sent_speed_pct_ = m.speed_pct;
        mode_sent_t_ = t_s;
        sent_retry();
      }
      break;
    }
    case ArmPhase::active: {
      if (!link) {
        set_phase(ArmPhase::no_link, "link down: targets stopped", t_s);
        break;
      }
      int disabled = -1;
      for (int j = 0; j < kNumJoints; ++j) {
        if (low_t_[j] > phase_t_ && !fb_.joint_enabled[j]) disabled = j;
      }
      if (status_since(phase_t_) && fb_.ctrl_mode != ctrl_mode::kCan) {
        set_phase(ArmPhase::enabling,
                  std::string("arm reports ctrl_mode ") + ctrl_mode_name(fb_.ctrl_mode) +
                      " (power cycle or mode change): re-running the enable sequence",
                  t_s);
      } else if (disabled >= 0) {
        set_phase(ArmPhase::enabling,
                  "joint" + std::to_string(disabled + 1) + " reports disabled: re-running the enable sequence",
                  t_s);
      } else if (status_since(phase_t_) && fb_.move_mode != move_mode::kMoveJ) {
        set_phase(ArmPhase::setting_mode,
                  std::string("arm reports ") + move_mode_name(fb_.move_mode) + " instead of move_j", t_s);
      } else {
        step_active(t_s, out);
      }
      break;
    }
    case ArmPhase::shutting_down:
    case ArmPhase::off:
      break;
  }
  update_fault_events(t_s);
}

void ArmDriver::step_active(double t_s, std::vector<can::CanFrame>& out) {
  const bool fresh = command_fresh(t_s);
  Hold next = Hold::streaming;
  if (!fresh) next = Hold::stale;
  else if (!cmd_.enabled) next = Hold::disabled_cmd;
  if (next != hold_state_) {
    if (next != Hold::streaming) hold_q_ = fb_.q_rad;  // latch where the arm is now
    if (next == Hold::streaming) {
      event(ArmEvent::Level::info, "ARM_CMD fresh: streaming targets");
    } else if (next == Hold::stale) {
      event(ArmEvent::Level::warn,
            cmd_t_ < 0.0 || cmd_t_ <= fresh_after_t_
                ? std::string("no ARM_CMD yet: holding the measured position")
                : "ARM_CMD stale (newest " + ms(t_s - cmd_t_) + " old): holding the measured position");
    } else {
      event(ArmEvent::Level::info, "ARM_CMD enabled = false: holding the measured position");
    }
    hold_state_ = next;
  }

  const int speed = desired_speed_pct(t_s);
  if (speed != sent_speed_pct_) {
    ModeCommand m;
    m.speed_pct = static_cast<std::uint8_t>(speed);
    emit(encode_mode(m), out);
    sent_speed_pct_ = speed;
  }

  JointArray target = hold_q_;
  bool clamped = false;
  std::string clamp_text;
  if (next == Hold::streaming) {
    for (int j = 0; j < kNumJoints; ++j) {
      const double q = cmd_.q_rad[j];
      target[j] = std::clamp(q, p_.lower_rad[j], p_.upper_rad[j]);
      if (target[j] != q) {
        clamped = true;
        if (clamp_text.empty()) {
          clamp_text = "joint" + std::to_string(j + 1) + " " + fmt("%.4f", q) + " -> " + fmt("%.4f rad", target[j]);
        }
      }
    }
  }
  if (clamped) ++counters_.targets_clamped;
  if (clamped != clamping_) {
    event(clamped ? ArmEvent::Level::warn : ArmEvent::Level::info,
          clamped ? "ARM_CMD target outside the joint limits, clamped: " + clamp_text
                  : "ARM_CMD targets within the joint limits again");
    clamping_ = clamped;
  }
  for (const can::CanFrame& f : encode_joint_targets(target)) emit(f, out);
  last_targets_ = target;

  if (next == Hold::streaming && cmd_.has_gripper) {
    const double stroke = std::clamp(cmd_.gripper_m, p_.gripper_min_m, p_.gripper_max_m);
    const double effort = std::clamp(cmd_.gripper_effort_nm, 0.0, p_.gripper_effort_max_nm);
    emit(encode_gripper(gripper_command(stroke, effort, gripper_code::kEnable)), out);
  }
}

void ArmDriver::step_shutdown(double t_s, std::vector<can::CanFrame>& out) {
  if (all_disabled_since(shutdown_t_)) {
    set_phase(ArmPhase::off, "every joint reports disabled after " + ms(t_s - shutdown_t_), t_s);
    return;
  }
  if (t_s - shutdown_t_ > p_.shutdown_timeout_s) {
    event(ArmEvent::Level::warn, "disable not confirmed within " + ms(p_.shutdown_timeout_s) +
                                     " (no low-speed feedback showing every joint disabled)");
    set_phase(ArmPhase::off, "shutdown timeout", t_s);
    return;
  }
  if (t_s >= next_send_t_) {
    emit(encode_enable({kMotorAll, false}), out);
    next_send_t_ = t_s + p_.retry_period_s;
  }
}

ArmDriverStatus ArmDriver::status(double t_s) const {
  ArmDriverStatus s;
  s.phase = phase_;
  s.link_ok = link_ok(t_s);
  s.enabled = std::all_of(fb_.joint_enabled.begin(), fb_.joint_enabled.end(), [](bool e) { return e; });
  s.holding = phase_ == ArmPhase::active && hold_state_ != Hold::streaming;
  s.cmd_stale = phase_ == ArmPhase::active && hold_state_ == Hold::stale;
  s.estop_active = estop_requested_;
  if (!s.link_ok) s.faults.push_back("no_link");
  if (fb_.have_status) {
    if (arm_status_is_fault(fb_.arm_status)) s.faults.push_back(arm_status_name(fb_.arm_status));
    append_err_code_names(fb_.err_code, s.faults);
  }
  // Motor frames never received count as stale only once the link has been up for the timeout
  // (the 40 Hz frames may follow the first status by up to 25 ms).
  auto stale = [&](double received_t) {
    const double since = received_t >= 0.0 ? received_t : link_up_t_;
    return link_up_t_ >= 0.0 && t_s - since > p_.motor_feedback_timeout_s;
  };
  bool motor_stale = false;
  for (int j = 0; j < kNumJoints; ++j) {
    if (stale(high_t_[j]) || stale(low_t_[j])) motor_stale = true;
    append_driver_status_names(fb_.driver_status[j] & kDriverFaultMask, "joint" + std::to_string(j + 1) + "_",
                               s.faults);
  }
  if (motor_stale && s.link_ok) s.faults.push_back("motor_feedback_stale");
  append_gripper_status_names(fb_.gripper_status & kGripperFaultMask, "gripper_", s.faults);
  s.fault = !s.faults.empty();
  return s;
}

void ArmDriver::update_fault_events(double t_s) {
  const std::string now = join_names(status(t_s).faults);
  if (now == last_faults_) return;
  if (now.empty()) {
    event(ArmEvent::Level::info, "faults cleared (were: " + last_faults_ + ")");
  } else {
    event(ArmEvent::Level::warn, "faults: " + now);
  }
  last_faults_ = now;
}

}  // namespace porter::piper
