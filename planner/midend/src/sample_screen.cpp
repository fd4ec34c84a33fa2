#include "sample_screen.hpp"

#include <algorithm>
#include <cmath>

#include "nearest_node.hpp"

namespace porter::midend::detail {
namespace {

constexpr int kDim = kTrajDim;
constexpr double kPiSquaredOver4 = 2.4674011002723395;  // (pi / 2)^2
constexpr double kHuge = 1e300;

}  // namespace

static_assert(1 + 3 * kDim + 2 + 1 <= kWorkRows, "sampler workspace too small");

SampleRows evaluate_samples(const double* C, double duration_s, int kappa, double* work) {
  const int n = kappa + 1;
  SampleRows r;
  r.t = work;
  r.pos = r.t + n;
  r.vel = r.pos + kDim * n;
  r.acc = r.vel + kDim * n;
  r.jerk_xy = r.acc + kDim * n;
  r.screen = r.jerk_xy + 2 * n;
  // |z^(k)(t)| <= sum_i i!/(i-k)! |c_i| t^(i-k) <= 90 sum|c| max(1, T)^5 on [0, T], k <= 3
  // (a sum, not a max, so that a NaN propagates).
  double col_sum[kDim] = {};  // per column: independent additions the compiler vectorises
  for (int i = 0; i < 6; ++i) {
    for (int d = 0; d < kDim; ++d) col_sum[d] += std::abs(C[i * kDim + d]);
  }
  double c_sum = 0.0;
  for (int d = 0; d < kDim; ++d) c_sum += col_sum[d];
  const double t1 = std::max(1.0, duration_s);
  r.moderate = 90.0 * c_sum * t1 * t1 * t1 * t1 * t1 <= kScreenMagnitude;
  for (int j = 0; j < n; ++j) r.t[j] = (static_cast<double>(j) / kappa) * duration_s;
  const double* t = r.t;
  for (int d = 0; d < kDim; ++d) {
    const double c0 = C[d], c1 = C[kDim + d], c2 = C[2 * kDim + d], c3 = C[3 * kDim + d],
                 c4 = C[4 * kDim + d], c5 = C[5 * kDim + d];
    double* pos = r.pos + d * n;
    double* vel = r.vel + d * n;
    double* acc = r.acc + d * n;
    for (int j = 0; j < n; ++j) {
      pos[j] = c0 + t[j] * (c1 + t[j] * (c2 + t[j] * (c3 + t[j] * (c4 + t[j] * c5))));
    }
    for (int j = 0; j < n; ++j) {
      vel[j] = c1 + t[j] * (2.0 * c2 + t[j] * (3.0 * c3 + t[j] * (4.0 * c4 + t[j] * 5.0 * c5)));
    }
    for (int j = 0; j < n; ++j) acc[j] = 2.0 * c2 + t[j] * (6.0 * c3 + t[j] * (12.0 * c4 + t[j] * 20.0 * c5));
  }
  for (int d = 0; d < 2; ++d) {
    const double c3 = C[3 * kDim + d], c4 = C[4 * kDim + d], c5 = C[5 * kDim + d];
    double* jerk = r.jerk_xy + d * n;
    for (int j = 0; j < n; ++j) jerk[j] = 6.0 * c3 + t[j] * (24.0 * c4 + t[j] * 60.0 * c5);
  }
  return r;
}

void screen_samples(const SamplerConstants& k, const PieceInputs& in, const SampleRows& r,
                    int kappa, bool min_speed, double inv_vmin2, bool wheels_on, bool joints_on,
                    bool residual_on) {
  const int n = kappa + 1;
  double* screen = r.screen;
  for (int j = 0; j < n; ++j) screen[j] = -1.0;
  const double* vx = r.vel;
  const double* vy = r.vel + n;
  if (wheels_on) {
    const double* ax = r.acc;
    const double* ay = r.acc + n;
    const double* jx = r.jerk_xy;
    const double* jy = r.jerk_xy + n;
    const double eta = in.eta;
    const double wv = k.wheel_velocity ? 1.0 : 0.0, wa = k.wheel_acceleration ? 1.0 : 0.0;
    for (int j = 0; j < n; ++j) {
      const double n2 = vx[j] * vx[j] + vy[j] * vy[j] + k.speed_guard2;
      const double inv_n2 = 1.0 / n2;
      const double speed = std::sqrt(n2);
      const double c = vx[j] * ay[j] - vy[j] * ax[j], e = vx[j] * ax[j] + vy[j] * ay[j],
                   d = vx[j] * jy[j] - vy[j] * jx[j];
      const double accel = e * speed * inv_n2;  // e / speed up to rounding (kScreenSlack)
      const double yaw_rate = c * inv_n2;
      const double yaw_accel = d * inv_n2 - 2.0 * c * e * inv_n2 * inv_n2;
      const double wl = (eta * speed - k.half_track_m * yaw_rate) * k.inv_wheel_radius;
      const double wr = (eta * speed + k.half_track_m * yaw_rate) * k.inv_wheel_radius;
      const double al = (eta * accel - k.half_track_m * yaw_accel) * k.inv_wheel_radius;
      const double ar = (eta * accel + k.half_track_m * yaw_accel) * k.inv_wheel_radius;
      // A disabled term contributes -1 (never active).
      const double xv = wv * (std::max(wl * wl, wr * wr) * k.inv_omega_max2) - 1.0;
      const double xa = wa * (std::max(al * al, ar * ar) * k.inv_alpha_max2) - 1.0;
      screen[j] = std::max(screen[j], std::max(xv, xa));
    }
  }
  if (min_speed) {
    for (int j = 0; j < n; ++j) {
      screen[j] = std::max(screen[j], 1.0 - (vx[j] * vx[j] + vy[j] * vy[j]) * inv_vmin2);
    }
  }
  if (joints_on) {
    for (int d = 0; d < kNumArmJoints; ++d) {
      const double* q = r.pos + (2 + d) * n;
      const double* qd = r.vel + (2 + d) * n;
      const double* qdd = r.acc + (2 + d) * n;
      const double lo = k.joint_position ? k.lower_rad[d] : -kHuge;
      const double hi = k.joint_position ? k.upper_rad[d] : kHuge;
      const double iv = k.joint_velocity ? k.inv_qd_max2[d] : 0.0;
      const double ia = k.joint_acceleration ? k.inv_qdd_max2[d] : 0.0;
      for (int j = 0; j < n; ++j) {
        const double xp = std::max(q[j] - hi, lo - q[j]);
        const double xq = std::max(qd[j] * qd[j] * iv, qdd[j] * qdd[j] * ia) - 1.0;
        screen[j] = std::max(screen[j], std::max(xp, xq));
      }
    }
  }
  if (!residual_on) return;
  const bool base = k.residual_base && !in.base_still;
  // Runs of samples sharing their nearest node (nearest_node.hpp), each screened against it.
  int node = 0;
  for (int j0 = 0; j0 < n;) {
    bool tie = false;
    nearest_node(in.fractions, in.num_edges, j0, kappa, &node, &tie);
    if (tie) {
      screen[j0++] = 1.0;
      continue;
    }
    int j1 = j0 + 1;
    if (node < in.num_edges) {
      const double mid = kappa * (in.fractions[node] + in.fractions[node + 1]);
      while (j1 < n && 2.0 * j1 < mid) ++j1;
    } else {
      j1 = n;
    }
    const RobotConfiguration& ref = in.nodes[node];
    if (base) {
      const double* px = r.pos;
      const double* py = r.pos + n;
      const double ux = in.dirs[node][0], uy = in.dirs[node][1];
      const double eta = in.eta;
      const double yaw_term = k.yaw_weight_m2 * kPiSquaredOver4;
      // The exact path's skip bound (residual(): dp2 + yaw_term cross^2 / (v2 + gate2) < rho_b2
      // (1 - 1e-12)) with a wider margin, so that this division-free form is conservative.
      const double bound = k.rho_b2 * (1.0 - 1e-9);
      const double x0 = ref.base.x_m, y0 = ref.base.y_m;
      for (int j = j0; j < j1; ++j) {
        const double dx = px[j] - x0, dy = py[j] - y0;
        const double cross = eta * (ux * vy[j] - uy * vx[j]), dot = eta * (ux * vx[j] + uy * vy[j]);
        const double v2 = vx[j] * vx[j] + vy[j] * vy[j];
        const double dp2 = dx * dx + dy * dy;
        const bool skip = dot >= 0.0 && (dp2 - bound) * (v2 + k.gate2) + yaw_term * cross * cross < 0.0;
        screen[j] = skip ? screen[j] : 1.0;
      }
    }
    if (k.residual_arm) {
      const double* q1 = r.pos + 2 * n;
      const double* q2 = q1 + n;
      const double* q3 = q2 + n;
      const double* q4 = q3 + n;
      const double* q5 = q4 + n;
      const double* q6 = q5 + n;
      const JointVector& q0 = ref.q_rad;
      const double a1 = q0[0], a2 = q0[1], a3 = q0[2], a4 = q0[3], a5 = q0[4], a6 = q0[5];
      for (int j = j0; j < j1; ++j) {
        const double d1 = q1[j] - a1, d2 = q2[j] - a2, d3 = q3[j] - a3, d4 = q4[j] - a4,
                     d5 = q5[j] - a5, d6 = q6[j] - a6;
        const double sum = d1 * d1 + d2 * d2 + d3 * d3 + d4 * d4 + d5 * d5 + d6 * d6;
        screen[j] = std::max(screen[j], sum * k.inv_rho_m2 - 1.0);
      }
    }
    j0 = j1;
  }
}

}  // namespace porter::midend::detail
