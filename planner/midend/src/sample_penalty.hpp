#pragma once
// Internal: the mid-end's penalty integrand at one sample of one piece (wheel rates, joint
// limits, pose residuals). Used by midend_problem.cpp through minco::integrate_piece_penalty.

#include <cstdint>

#include "porter/core/types.hpp"
#include "porter/planner/angle.hpp"
#include "porter/midend/diff_drive.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_problem.hpp"
#include "porter/midend/midend_result.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/minco/penalty.hpp"
#include "porter/minco/penalty_integral.hpp"
#include "nearest_node.hpp"

namespace porter::midend::detail {

struct SamplePenalty {
  const MidendLimits* limits = nullptr;
  const MidendSettings* settings = nullptr;
  minco::PenaltyFunction penalty;
  std::uint32_t terms = kTermAll;
  int eta = 1;
  int num_edges = 1;                               ///< reference edges of the piece (m)
  const RobotConfiguration* nodes = nullptr;       ///< its m + 1 reference nodes
  const double* fractions = nullptr;               ///< their time fractions (nearest_node.hpp)
  double duration_s = 0.0;                         ///< piece duration (for the breakdown)
  double min_speed_mps = 0.0;                      ///< > 0: keep |v_xy| above it
  bool base_still = false;                         ///< still segment: no base terms
  CostBreakdown* breakdown = nullptr;              ///< integrated per-term costs, if non-null

  double operator()(minco::PenaltySample<kTrajDim>& s) const {
    s.grad_pos.setZero();
    s.grad_vel.setZero();
    s.grad_acc.setZero();
    s.grad_jerk.setZero();
    CostBreakdown g;  // this sample's integrand values, by term
    if (!base_still) wheels(s, g);
    joints(s, g);
    if ((terms & kTermMinSpeed) && !base_still && min_speed_mps > 0.0 && settings->weight_min_speed > 0.0) {
      const Eigen::Vector2d v = s.vel.head<2>();
      const double inv = 1.0 / (min_speed_mps * min_speed_mps);
      double dphi = 0.0;
      const double w = settings->weight_min_speed;
      g.min_speed += w * penalty.value(1.0 - v.squaredNorm() * inv, &dphi);
      if (dphi != 0.0) s.grad_vel.head<2>() -= (w * dphi * 2.0 * inv) * v;
    }
    if (terms & (kTermResidualBase | kTermResidualArm)) {
      int k = 0;
      bool tie = false;
      nearest_node(fractions, num_edges, s.index, s.kappa, &k, &tie);
      residual(s, nodes[k], tie ? 0.5 : 1.0, g);
      if (tie) residual(s, nodes[k + 1], 0.5, g);
    }
    if (breakdown) {
      const double w = (s.index == 0 || s.index == s.kappa ? 0.5 : 1.0) * duration_s / s.kappa;
      breakdown->wheel_velocity += w * g.wheel_velocity;
      breakdown->wheel_acceleration += w * g.wheel_acceleration;
      breakdown->joint_position += w * g.joint_position;
      breakdown->joint_velocity += w * g.joint_velocity;
      breakdown->joint_acceleration += w * g.joint_acceleration;
      breakdown->residual_base += w * g.residual_base;
      breakdown->residual_arm += w * g.residual_arm;
      breakdown->min_speed += w * g.min_speed;
    }
    return g.total();
  }

 private:
  /// weight * phi((value^2 / bound^2) - 1); returns d(cost)/d(value) and adds cost to *acc.
  double bounded_square(double value, double bound, double weight, double* acc) const {
    double dphi = 0.0;
    const double inv_b2 = 1.0 / (bound * bound);
    const double phi = penalty.value(value * value * inv_b2 - 1.0, &dphi);
    *acc += weight * phi;
    return weight * dphi * 2.0 * value * inv_b2;
  }

  void wheels(minco::PenaltySample<kTrajDim>& s, CostBreakdown& g) const {
    const bool wv = (terms & kTermWheelVelocity) && settings->weight_wheel_velocity > 0.0;
    const bool wa = (terms & kTermWheelAcceleration) && settings->weight_wheel_acceleration > 0.0;
    if (!wv && !wa) return;
    const Eigen::Vector2d v = s.vel.head<2>(), a = s.acc.head<2>(), j = s.jerk.head<2>();
    const BaseRates r = base_rates(v, a, j, settings->speed_guard_mps);
    const double half = 0.5 * limits->track_width_m;
    const double inv_r = 1.0 / limits->wheel_radius_m;
    for (const double side : {-1.0, 1.0}) {  // left, right
      if (wv) {
        const double w = (eta * r.speed + side * half * r.yaw_rate) * inv_r;
        const double c = inv_r * bounded_square(w, settings->limit_penalty_fraction * limits->wheel_omega_max_radps,
                                                settings->weight_wheel_velocity, &g.wheel_velocity);
        if (c != 0.0) {
          s.grad_vel.head<2>() += c * (eta * r.dspeed_dv + side * half * r.dyaw_rate_dv);
          s.grad_acc.head<2>() += c * side * half * r.dyaw_rate_da;
        }
      }
      if (wa) {
        const double al = (eta * r.accel + side * half * r.yaw_accel) * inv_r;
        const double c = inv_r * bounded_square(al, settings->limit_penalty_fraction * limits->wheel_alpha_max_radps2,
                                                settings->weight_wheel_acceleration,
                                                &g.wheel_acceleration);
        if (c != 0.0) {
          s.grad_vel.head<2>() += c * (eta * r.daccel_dv + side * half * r.dyaw_accel_dv);
          s.grad_acc.head<2>() += c * (eta * r.daccel_da + side * half * r.dyaw_accel_da);
          s.grad_jerk.head<2>() += c * side * half * r.dyaw_accel_dj;
        }
      }
    }
  }

  void joints(minco::PenaltySample<kTrajDim>& s, CostBreakdown& g) const {
    const bool jp = (terms & kTermJointPosition) && settings->weight_joint_position > 0.0;
    const bool jv = (terms & kTermJointVelocity) && settings->weight_joint_velocity > 0.0;
    const bool ja = (terms & kTermJointAcceleration) && settings->weight_joint_acceleration > 0.0;
    for (int d = 0; d < kNumArmJoints; ++d) {
      const int k = 2 + d;
      if (jp) {
        const double w = settings->weight_joint_position;
        double dphi = 0.0;
        g.joint_position += w * penalty.value(s.pos[k] - limits->joint_upper_rad[d], &dphi);
        s.grad_pos[k] += w * dphi;
        g.joint_position += w * penalty.value(limits->joint_lower_rad[d] - s.pos[k], &dphi);
        s.grad_pos[k] -= w * dphi;
      }
      if (jv) {
        s.grad_vel[k] += bounded_square(s.vel[k], settings->limit_penalty_fraction * limits->joint_velocity_max_radps[d],
                                        settings->weight_joint_velocity, &g.joint_velocity);
      }
      if (ja) {
        s.grad_acc[k] += bounded_square(s.acc[k], settings->limit_penalty_fraction * limits->joint_acceleration_max_radps2[d],
                                        settings->weight_joint_acceleration,
                                        &g.joint_acceleration);
      }
    }
  }

  void residual(minco::PenaltySample<kTrajDim>& s, const RobotConfiguration& node, double share,
                CostBreakdown& g) const {
    if ((terms & kTermResidualBase) && !base_still && settings->weight_residual_base > 0.0) {
      const Eigen::Vector2d dp(s.pos[0] - node.base.x_m, s.pos[1] - node.base.y_m);
      const Eigen::Vector2d v = s.vel.head<2>();
      Eigen::Vector2d dphi_dv;
      const double phi = heading_from_velocity(v, eta, &dphi_dv);
      const double dyaw = planner::angle_difference_rad(phi, node.base.yaw_rad);
      const double v2 = v.squaredNorm();
      const double gate2 = settings->yaw_gate_speed_mps * settings->yaw_gate_speed_mps;
      const double gate = v2 / (v2 + gate2);
      const Eigen::Vector2d dgate_dv = (2.0 * gate2 / ((v2 + gate2) * (v2 + gate2))) * v;
      const double wphi = settings->residual_yaw_weight_m2;
      const double rho = settings->residual_penalty_fraction * settings->residual_base_bound_m;
      const double rho2 = rho * rho;
      const double e = dp.squaredNorm() + wphi * gate * dyaw * dyaw;
      double dpen = 0.0;
      const double w = share * settings->weight_residual_base;
      g.residual_base += w * penalty.value(e / rho2 - 1.0, &dpen);
      const double c = w * dpen / rho2;
      if (c != 0.0) {
        s.grad_pos.head<2>() += c * 2.0 * dp;
        s.grad_vel.head<2>() += c * wphi * (dyaw * dyaw * dgate_dv + 2.0 * gate * dyaw * dphi_dv);
      }
    }
    if ((terms & kTermResidualArm) && settings->weight_residual_arm > 0.0) {
      const JointVector dq = s.pos.tail<kNumArmJoints>() - node.q_rad;
      const double rho = settings->residual_penalty_fraction * settings->residual_arm_bound_rad;
      const double rho2 = rho * rho;
      double dpen = 0.0;
      const double w = share * settings->weight_residual_arm;
      g.residual_arm += w * penalty.value(dq.squaredNorm() / rho2 - 1.0, &dpen);
      const double c = w * dpen / rho2;
      if (c != 0.0) s.grad_pos.tail<kNumArmJoints>() += c * 2.0 * dq;
    }
  }
};

}  // namespace porter::midend::detail
