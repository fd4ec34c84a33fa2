#include "piece_sampler.hpp"

#include <algorithm>
#include <cmath>

#include "porter/midend/diff_drive.hpp"
#include "porter/midend/midend_problem.hpp"
#include "nearest_node.hpp"
#include "sample_screen.hpp"

namespace porter::midend::detail {
namespace {

constexpr int kDim = kTrajDim;        // 8 outputs: p_x, p_y, q1..q6
constexpr double kPiSquaredOver4 = 2.4674011002723395;  // (pi / 2)^2

struct Sample {
  double pos[kDim], vel[kDim], acc[kDim];
  double jerk_xy[2], snap_xy[2];
  double gp[kDim], gv[kDim], ga[kDim], gj[2];  // d integrand / d z^(k)
  bool joints_touched = false;  // some joint partial is non-zero
  bool any = false;             // some partial is non-zero
};

/// weight * phi(value^2 * inv_b2 - 1) added to *acc; returns d/d value (0 when feasible).
inline double bounded_square(const minco::PenaltyFunction& pen, double value, double inv_b2,
                             double weight, double* acc) {
  const double x = value * value * inv_b2 - 1.0;
  if (x <= 0.0) return 0.0;
  double dphi = 0.0;
  *acc += weight * pen.value(x, &dphi);
  return weight * dphi * 2.0 * value * inv_b2;
}

void wheels(const SamplerConstants& k, int eta, Sample& s, CostBreakdown& g) {
  const double vx = s.vel[0], vy = s.vel[1], ax = s.acc[0], ay = s.acc[1];
  const double jx = s.jerk_xy[0], jy = s.jerk_xy[1];
  const double n2 = vx * vx + vy * vy + k.speed_guard2;
  const double inv_n2 = 1.0 / n2;
  const double speed = std::sqrt(n2);
  const double c = vx * ay - vy * ax, e = vx * ax + vy * ay, d = vx * jy - vy * jx;
  const double accel = e / speed;
  const double yaw_rate = c * inv_n2;
  const double yaw_accel = d * inv_n2 - 2.0 * c * e * inv_n2 * inv_n2;
  double cv[2] = {0.0, 0.0}, ca[2] = {0.0, 0.0};  // d cost / d wheel rate, per side
  bool hit = false;
  for (int i = 0; i < 2; ++i) {
    const double side = i == 0 ? -1.0 : 1.0;
    if (k.wheel_velocity) {
      const double w = (eta * speed + side * k.half_track_m * yaw_rate) * k.inv_wheel_radius;
      cv[i] = k.inv_wheel_radius * bounded_square(k.penalty, w, k.inv_omega_max2,
                                                  k.w_wheel_velocity, &g.wheel_velocity);
      hit = hit || cv[i] != 0.0;
    }
    if (k.wheel_acceleration) {
      const double al = (eta * accel + side * k.half_track_m * yaw_accel) * k.inv_wheel_radius;
      ca[i] = k.inv_wheel_radius * bounded_square(k.penalty, al, k.inv_alpha_max2,
                                                  k.w_wheel_acceleration, &g.wheel_acceleration);
      hit = hit || ca[i] != 0.0;
    }
  }
  if (!hit) return;
  const BaseRates r = base_rates(Eigen::Vector2d(vx, vy), Eigen::Vector2d(ax, ay),
                                 Eigen::Vector2d(jx, jy), std::sqrt(k.speed_guard2));
  Eigen::Vector2d gv = Eigen::Vector2d::Zero(), ga = Eigen::Vector2d::Zero(),
                  gj = Eigen::Vector2d::Zero();
  for (int i = 0; i < 2; ++i) {
    const double sh = (i == 0 ? -1.0 : 1.0) * k.half_track_m;
    if (cv[i] != 0.0) {
      gv += cv[i] * (eta * r.dspeed_dv + sh * r.dyaw_rate_dv);
      ga += cv[i] * sh * r.dyaw_rate_da;
    }
    if (ca[i] != 0.0) {
      gv += ca[i] * (eta * r.daccel_dv + sh * r.dyaw_accel_dv);
      ga += ca[i] * (eta * r.daccel_da + sh * r.dyaw_accel_da);
      gj += ca[i] * sh * r.dyaw_accel_dj;
    }
  }
  s.gv[0] += gv.x();
  s.gv[1] += gv.y();
  s.ga[0] += ga.x();
  s.ga[1] += ga.y();
  s.gj[0] += gj.x();
  s.gj[1] += gj.y();
  s.any = true;
}

void joints(const SamplerConstants& k, Sample& s, CostBreakdown& g) {
  for (int d = 0; d < kNumArmJoints; ++d) {
    const int o = 2 + d;
    if (k.joint_position) {
      const double over = s.pos[o] - k.upper_rad[d], under = k.lower_rad[d] - s.pos[o];
      double dphi = 0.0;
      if (over > 0.0) {
        g.joint_position += k.w_joint_position * k.penalty.value(over, &dphi);
        s.gp[o] += k.w_joint_position * dphi;
        s.joints_touched = s.any = true;
      }
      if (under > 0.0) {
        g.joint_position += k.w_joint_position * k.penalty.value(under, &dphi);
        s.gp[o] -= k.w_joint_position * dphi;
        s.joints_touched = s.any = true;
      }
    }
    if (k.joint_velocity) {
      const double c = bounded_square(k.penalty, s.vel[o], k.inv_qd_max2[d], k.w_joint_velocity,
                                      &g.joint_velocity);
      if (c != 0.0) {
        s.gv[o] += c;
        s.joints_touched = s.any = true;
      }
    }
    if (k.joint_acceleration) {
      const double c = bounded_square(k.penalty, s.acc[o], k.inv_qdd_max2[d],
                                      k.w_joint_acceleration, &g.joint_acceleration);
      if (c != 0.0) {
        s.ga[o] += c;
        s.joints_touched = s.any = true;
      }
    }
  }
}

void residual(const SamplerConstants& k, int eta, bool base, const RobotConfiguration& node,
              const double* dir, double share, Sample& s, CostBreakdown& g) {
  if (base && k.residual_base) {
    const double dx = s.pos[0] - node.base.x_m, dy = s.pos[1] - node.base.y_m;
    const double vx = s.vel[0], vy = s.vel[1];
    const double ux = dir[0], uy = dir[1];
    // Heading difference dyaw = angle(eta v) - yaw_node = atan2(u x w, u . w), w = eta v.
    const double cross = eta * (ux * vy - uy * vx), dot = eta * (ux * vx + uy * vy);
    const double v2 = vx * vx + vy * vy;
    const double dp2 = dx * dx + dy * dy;
    // Upper bound: for u . w >= 0, |dyaw| <= (pi/2) |sin dyaw|; gate * sin^2 = cross^2 / (v2 + gate2).
    const bool skip = dot >= 0.0 &&
                      dp2 + k.yaw_weight_m2 * kPiSquaredOver4 * cross * cross / (v2 + k.gate2) <
                          k.rho_b2 * (1.0 - 1e-12);
    if (!skip) {
      const double dyaw = std::atan2(cross, dot);
      const double den = v2 + k.gate2;
      const double gate = v2 / den;
      const double e = dp2 + k.yaw_weight_m2 * gate * dyaw * dyaw;
      const double x = e * k.inv_rho_b2 - 1.0;
      if (x > 0.0) {
        double dpen = 0.0;
        const double w = share * k.w_residual_base;
        g.residual_base += w * k.penalty.value(x, &dpen);
        const double c = w * dpen * k.inv_rho_b2;
        if (c != 0.0) {
          s.gp[0] += c * 2.0 * dx;
          s.gp[1] += c * 2.0 * dy;
          const double dg = 2.0 * k.gate2 / (den * den);  // d gate / d v = dg * v
          const double dphi = v2 > 0.0 ? 1.0 / v2 : 0.0;  // d heading / d v = dphi * (-vy, vx)
          const double a = c * k.yaw_weight_m2;
          s.gv[0] += a * (dyaw * dyaw * dg * vx - 2.0 * gate * dyaw * dphi * vy);
          s.gv[1] += a * (dyaw * dyaw * dg * vy + 2.0 * gate * dyaw * dphi * vx);
          s.any = true;
        }
      }
    }
  }
  if (k.residual_arm) {
    double dq[kNumArmJoints];
    double n2 = 0.0;
    for (int d = 0; d < kNumArmJoints; ++d) {
      dq[d] = s.pos[2 + d] - node.q_rad[d];
      n2 += dq[d] * dq[d];
    }
    const double x = n2 * k.inv_rho_m2 - 1.0;
    if (x > 0.0) {
      double dpen = 0.0;
      const double w = share * k.w_residual_arm;
      g.residual_arm += w * k.penalty.value(x, &dpen);
      const double c = w * dpen * k.inv_rho_m2;
      if (c != 0.0) {
        for (int d = 0; d < kNumArmJoints; ++d) s.gp[2 + d] += c * 2.0 * dq[d];
        s.joints_touched = s.any = true;
      }
    }
  }
}

}  // namespace

SamplerConstants::SamplerConstants(const MidendLimits& limits, const MidendSettings& st,
                                   std::uint32_t terms) {
  penalty.kind = st.penalty_kind;
  penalty.mu = st.penalty_smoothing;
  auto on = [terms](std::uint32_t bit, double w) { return (terms & bit) && w > 0.0; };
  wheel_velocity = on(kTermWheelVelocity, st.weight_wheel_velocity);
  wheel_acceleration = on(kTermWheelAcceleration, st.weight_wheel_acceleration);
  joint_position = on(kTermJointPosition, st.weight_joint_position);
  joint_velocity = on(kTermJointVelocity, st.weight_joint_velocity);
  joint_acceleration = on(kTermJointAcceleration, st.weight_joint_acceleration);
  residual_base = on(kTermResidualBase, st.weight_residual_base);
  residual_arm = on(kTermResidualArm, st.weight_residual_arm);
  min_speed = on(kTermMinSpeed, st.weight_min_speed);
  w_wheel_velocity = st.weight_wheel_velocity;
  w_wheel_acceleration = st.weight_wheel_acceleration;
  w_joint_position = st.weight_joint_position;
  w_joint_velocity = st.weight_joint_velocity;
  w_joint_acceleration = st.weight_joint_acceleration;
  w_residual_base = st.weight_residual_base;
  w_residual_arm = st.weight_residual_arm;
  w_min_speed = st.weight_min_speed;
  half_track_m = 0.5 * limits.track_width_m;
  inv_wheel_radius = 1.0 / limits.wheel_radius_m;
  const double f = st.limit_penalty_fraction;  // penalties start at f * limit
  inv_omega_max2 = 1.0 / (f * f * limits.wheel_omega_max_radps * limits.wheel_omega_max_radps);
  inv_alpha_max2 = 1.0 / (f * f * limits.wheel_alpha_max_radps2 * limits.wheel_alpha_max_radps2);
  speed_guard2 = st.speed_guard_mps * st.speed_guard_mps;
  lower_rad = limits.joint_lower_rad;
  upper_rad = limits.joint_upper_rad;
  inv_qd_max2 = (f * limits.joint_velocity_max_radps.array()).square().inverse();
  inv_qdd_max2 = (f * limits.joint_acceleration_max_radps2.array()).square().inverse();
  const double rho_b = st.residual_penalty_fraction * st.residual_base_bound_m;
  const double rho_m = st.residual_penalty_fraction * st.residual_arm_bound_rad;
  rho_b2 = rho_b * rho_b;
  inv_rho_b2 = 1.0 / rho_b2;
  inv_rho_m2 = 1.0 / (rho_m * rho_m);
  yaw_weight_m2 = st.residual_yaw_weight_m2;
  gate2 = st.yaw_gate_speed_mps * st.yaw_gate_speed_mps;
}

int sampler_work_size(int max_kappa) { return kWorkRows * (max_kappa + 1); }

double sample_piece(const SamplerConstants& k, const PieceInputs& in, const double* C,
                    double duration_s, int kappa, double* work, double* grad_c, double* grad_t,
                    CostBreakdown* breakdown) {
  const int n = kappa + 1;
  const double h = duration_s / kappa;
  const bool min_speed = k.min_speed && in.min_speed_mps > 0.0 && !in.base_still;
  const double inv_vmin2 = min_speed ? 1.0 / (in.min_speed_mps * in.min_speed_mps) : 0.0;
  const bool wheels_on = (k.wheel_velocity || k.wheel_acceleration) && !in.base_still;
  const bool joints_on = k.joint_position || k.joint_velocity || k.joint_acceleration;
  const bool residual_on = (k.residual_base && !in.base_still) || k.residual_arm;

  const SampleRows rows = evaluate_samples(C, duration_s, kappa, work);
  screen_samples(k, in, rows, kappa, min_speed, inv_vmin2, wheels_on, joints_on, residual_on);

  double total = 0.0, gt = 0.0;
  CostBreakdown sums;  // integrals of each term over the piece
  int node = 0;        // nearest reference node (piece-local), advanced with j
  for (int j = 0; j < n; ++j) {
    // Provably zero value and partials (finite samples of moderate size only: the screen's
    // products must not overflow).
    if (rows.moderate && rows.screen[j] <= -kScreenSlack) continue;
    const double frac = static_cast<double>(j) / kappa;
    const double t = rows.t[j];
    Sample s;
    for (int d = 0; d < kDim; ++d) {
      s.pos[d] = rows.pos[d * n + j];
      s.vel[d] = rows.vel[d * n + j];
      s.acc[d] = rows.acc[d * n + j];
      s.gp[d] = s.gv[d] = s.ga[d] = 0.0;
    }
    for (int d = 0; d < 2; ++d) {
      s.jerk_xy[d] = rows.jerk_xy[d * n + j];
      s.snap_xy[d] = 24.0 * C[4 * kDim + d] + t * 120.0 * C[5 * kDim + d];
      s.gj[d] = 0.0;
    }
    CostBreakdown g;  // this sample's integrand, by term
    if (wheels_on) wheels(k, in.eta, s, g);
    if (joints_on) joints(k, s, g);
    if (min_speed) {
      const double v2 = s.vel[0] * s.vel[0] + s.vel[1] * s.vel[1];
      const double x = 1.0 - v2 * inv_vmin2;
      if (x > 0.0) {
        double dphi = 0.0;
        g.min_speed += k.w_min_speed * k.penalty.value(x, &dphi);
        const double c = k.w_min_speed * dphi * 2.0 * inv_vmin2;
        if (c != 0.0) {
          s.gv[0] -= c * s.vel[0];
          s.gv[1] -= c * s.vel[1];
          s.any = true;
        }
      }
    }
    if (residual_on) {
      bool tie = false;
      nearest_node(in.fractions, in.num_edges, j, kappa, &node, &tie);
      const double share = tie ? 0.5 : 1.0;
      residual(k, in.eta, !in.base_still, in.nodes[node], in.dirs[node].data(), share, s, g);
      if (tie) residual(k, in.eta, !in.base_still, in.nodes[node + 1], in.dirs[node + 1].data(), share, s, g);
    }
    const double value = g.total();
    if (value == 0.0 && !s.any) continue;
    const double w = (j == 0 || j == kappa) ? 0.5 : 1.0;
    const double wh = w * h;
    total += wh * value;
    sums.wheel_velocity += wh * g.wheel_velocity;
    sums.wheel_acceleration += wh * g.wheel_acceleration;
    sums.joint_position += wh * g.joint_position;
    sums.joint_velocity += wh * g.joint_velocity;
    sums.joint_acceleration += wh * g.joint_acceleration;
    sums.residual_base += wh * g.residual_base;
    sums.residual_arm += wh * g.residual_arm;
    sums.min_speed += wh * g.min_speed;
    double chain = 0.0;  // sum_k (dG/dz^(k)) . z^(k+1)
    if (s.any) {
      const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
      const double b0[6] = {1.0, t, t2, t3, t4, t5};
      const double b1[6] = {0.0, 1.0, 2.0 * t, 3.0 * t2, 4.0 * t3, 5.0 * t4};
      const double b2[6] = {0.0, 0.0, 2.0, 6.0 * t, 12.0 * t2, 20.0 * t3};
      const double b3[6] = {0.0, 0.0, 0.0, 6.0, 24.0 * t, 60.0 * t2};
      const int dims = s.joints_touched ? kDim : 2;
      for (int r = 0; r < 6; ++r) {
        double* row = grad_c + r * kDim;
        const double p0 = wh * b0[r], p1 = wh * b1[r], p2 = wh * b2[r], p3 = wh * b3[r];
        row[0] += p0 * s.gp[0] + p1 * s.gv[0] + p2 * s.ga[0] + p3 * s.gj[0];
        row[1] += p0 * s.gp[1] + p1 * s.gv[1] + p2 * s.ga[1] + p3 * s.gj[1];
        for (int d = 2; d < dims; ++d) row[d] += p0 * s.gp[d] + p1 * s.gv[d] + p2 * s.ga[d];
      }
      for (int d = 0; d < 2; ++d) {
        chain += s.gp[d] * s.vel[d] + s.gv[d] * s.acc[d] + s.ga[d] * s.jerk_xy[d] +
                 s.gj[d] * s.snap_xy[d];
      }
      for (int d = 2; d < dims; ++d) {
        chain += s.gp[d] * s.vel[d] + s.gv[d] * s.acc[d];
        if (s.ga[d] != 0.0) {
          const double jerk = 6.0 * C[3 * kDim + d] +
                              t * (24.0 * C[4 * kDim + d] + t * 60.0 * C[5 * kDim + d]);
          chain += s.ga[d] * jerk;
        }
      }
    }
    gt += w * (value / kappa + h * frac * chain);
  }
  *grad_t += gt;
  breakdown->wheel_velocity += sums.wheel_velocity;
  breakdown->wheel_acceleration += sums.wheel_acceleration;
  breakdown->joint_position += sums.joint_position;
  breakdown->joint_velocity += sums.joint_velocity;
  breakdown->joint_acceleration += sums.joint_acceleration;
  breakdown->residual_base += sums.residual_base;
  breakdown->residual_arm += sums.residual_arm;
  breakdown->min_speed += sums.min_speed;
  return total;
}

}  // namespace porter::midend::detail
