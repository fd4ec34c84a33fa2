#include "porter/state/fusion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "porter/state/pose2.hpp"

namespace porter::state {
namespace {

// In double: the stamps come from datagrams, and their int64 difference can overflow.
double age_s(std::int64_t now, std::int64_t then) { return (static_cast<double>(now) - static_cast<double>(then)) * 1e-6; }

bool finite(const BasePose& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.yaw_rad);
}

}  // namespace

const char* to_string(PoseSource source) {
  switch (source) {
    case PoseSource::none: return "none";
    case PoseSource::lio: return "LIO";
    case PoseSource::wheel_odom: return "wheel odometry";
  }
  return "unknown";
}

void FusionParams::validate() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("FusionParams: ") + what);
  };
  require(finite(start_pose), "start_pose must be finite");
  require(base_timeout_s > 0.0, "base_timeout_s must be > 0");
  require(arm_timeout_s > 0.0, "arm_timeout_s must be > 0");
  require(lio_timeout_s > 0.0, "lio_timeout_s must be > 0");
  require(lio_jump_m > 0.0, "lio_jump_m must be > 0");
  require(lio_jump_rad > 0.0, "lio_jump_rad must be > 0");
  require(odom_history_s > 0.0, "odom_history_s must be > 0");
  require(odom_reset_m > 0.0, "odom_reset_m must be > 0");
  require(odom_reset_rad > 0.0, "odom_reset_rad must be > 0");
  require(max_extrapolation_s >= 0.0, "max_extrapolation_s must be >= 0");
}

StateFusion::StateFusion(FusionParams params) : params_(std::move(params)) {
  params_.validate();
  T_W_odom_ = params_.start_pose;
}

OdometryUpdate StateFusion::on_odometry(const OdometrySample& sample, std::int64_t receive_utime) {
  OdometryUpdate update;
  if (odom_ && sample.utime <= odom_->utime) {
    // A stamp that goes backwards by more than the history is a restarted source; a small step
    // back is a reordered or repeated message.
    if (age_s(odom_->utime, sample.utime) <= params_.odom_history_s) {
      ++counters_.odometry_out_of_order;
      update.out_of_order = true;
      return update;
    }
    update.reset = true;
  }
  if (!odom_) {
    update.first = true;
    // Anchor: at the latest LIO pose when one came first, else at the configured start pose.
    const BasePose T_W_B = lio_ ? lio_->T_W_B : params_.start_pose;
    T_W_odom_ = compose(T_W_B, inverse(sample.T_odom_B));
  } else {
    const BasePose step = between(odom_->T_odom_B, sample.T_odom_B);
    if (std::hypot(step.x_m, step.y_m) > params_.odom_reset_m ||
        std::abs(step.yaw_rad) > params_.odom_reset_rad) {
      update.reset = true;
    }
    if (update.reset) {
      // Continue from the last world pose: T_W_odom' * T_odom_B(new) = T_W_odom * T_odom_B(old).
      const BasePose T_W_B = compose(T_W_odom_, odom_->T_odom_B);
      T_W_odom_ = compose(T_W_B, inverse(sample.T_odom_B));
      history_.clear();
      ++counters_.odometry_resets;
    }
  }
  odom_ = sample;
  odom_receive_utime_ = receive_utime;
  history_.push_back({sample.utime, sample.T_odom_B});
  const auto span = static_cast<std::int64_t>(params_.odom_history_s * 1e6);
  while (history_.size() > 2 && history_.front().utime < sample.utime - span) history_.pop_front();
  ++counters_.odometry;
  return update;
}

BasePose StateFusion::odom_at(std::int64_t utime, bool* outside) const {
  *outside = false;
  if (utime <= history_.front().utime) {
    *outside = utime < history_.front().utime;
    return history_.front().T_odom_B;
  }
  if (utime >= history_.back().utime) {
    // Newer than the newest odometry: extrapolate with its velocity, as the output does.
    const double dt = std::min(age_s(utime, history_.back().utime), params_.max_extrapolation_s);
    *outside = age_s(utime, history_.back().utime) > params_.max_extrapolation_s;
    return integrate_unicycle(history_.back().T_odom_B, odom_->v_mps, odom_->omega_radps, dt);
  }
  const auto after = std::upper_bound(
      history_.begin(), history_.end(), utime,
      [](std::int64_t t, const Stamped& s) { return t < s.utime; });
  const auto before = after - 1;
  const double s = static_cast<double>(utime - before->utime) /
                   static_cast<double>(after->utime - before->utime);
  return interpolate(before->T_odom_B, after->T_odom_B, s);
}

LioUpdate StateFusion::on_lio(const LioSample& sample, std::int64_t receive_utime) {
  LioUpdate update;
  if (!params_.use_lio) {
    update.ignored_reason = "LIO disabled by the config";
  } else if (!finite(sample.T_W_B)) {
    update.ignored_reason = "pose is not finite";
  } else if (lio_ && sample.utime <= lio_->utime &&
             age_s(lio_->utime, sample.utime) <= params_.odom_history_s) {
    update.ignored_reason = "stamp is not newer than the previous LIO pose";
  }
  if (!update.ignored_reason.empty()) {
    ++counters_.lio_ignored;
    return update;
  }
  update.used = true;
  if (odom_) {
    const BasePose odom = odom_at(sample.utime, &update.outside_history);
    const BasePose predicted = compose(T_W_odom_, odom);
    const BasePose jump = between(predicted, sample.T_W_B);
    update.jump_m = std::hypot(jump.x_m, jump.y_m);
    update.jump_rad = std::abs(jump.yaw_rad);
    // The first LIO pose replaces the configured start pose: not a jump.
    update.jumped = lio_.has_value() &&
                    (update.jump_m > params_.lio_jump_m || update.jump_rad > params_.lio_jump_rad);
    T_W_odom_ = compose(sample.T_W_B, inverse(odom));
  }
  if (update.jumped) ++counters_.lio_jumps;
  lio_ = sample;
  lio_receive_utime_ = receive_utime;
  ++counters_.lio;
  return update;
}

void StateFusion::on_arm(const ArmSample& sample, std::int64_t receive_utime) {
  arm_ = sample;
  arm_receive_utime_ = receive_utime;
  ++counters_.arm;
}

void StateFusion::on_estop(bool active) { estop_ = active; }

FusedState StateFusion::output(std::int64_t now_utime) const {
  FusedState out;
  out.utime = now_utime;
  const bool base_fresh = odom_ && age_s(now_utime, odom_receive_utime_) <= params_.base_timeout_s;
  const bool lio_fresh = lio_ && params_.use_lio &&
                         age_s(now_utime, lio_receive_utime_) <= params_.lio_timeout_s;
  const bool arm_fresh = arm_ && age_s(now_utime, arm_receive_utime_) <= params_.arm_timeout_s;
  out.base_valid = base_fresh;
  out.arm_valid = arm_fresh;
  if (odom_) {
    // Extrapolate the newest odometry to now (only while it is fresh: a stopped driver says
    // nothing about the motion since).
    const double dt =
        base_fresh ? std::clamp(age_s(now_utime, odom_->utime), 0.0, params_.max_extrapolation_s)
                   : 0.0;
    const BasePose odom =
        integrate_unicycle(odom_->T_odom_B, odom_->v_mps, odom_->omega_radps, dt);
    out.T_W_B = compose(T_W_odom_, odom);
    out.utime = odom_->utime + static_cast<std::int64_t>(dt * 1e6);
    out.v_mps = odom_->v_mps;
    out.omega_radps = odom_->omega_radps;
    out.base_utime = odom_->utime;
    out.pose_source = lio_fresh ? PoseSource::lio : PoseSource::wheel_odom;
    out.pose_utime = lio_fresh ? lio_->utime : odom_->utime;
    // With LIO fresh but odometry stale, the output is the latest LIO pose (the correction
    // anchors it to the last odometry sample), still a valid pose.
    out.pose_valid = base_fresh || lio_fresh;
  } else if (lio_) {
    out.T_W_B = lio_->T_W_B;
    out.utime = lio_->utime;
    out.pose_source = PoseSource::lio;
    out.pose_utime = lio_->utime;
    out.pose_valid = lio_fresh;
  }
  if (arm_) {
    out.has_arm = true;
    out.q_rad = arm_->q_rad;
    out.qd_radps = arm_->qd_radps;
    out.arm_utime = arm_->utime;
  }
  out.estop_active = estop_ || (base_fresh && odom_->estop_active) ||
                     (arm_fresh && arm_->estop_active);
  return out;
}

}  // namespace porter::state
