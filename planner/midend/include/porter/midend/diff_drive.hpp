#pragma once
// Differential-drive body rates from the planar flat output p_xy(t) and their gradients
// (paper eq. 1, kinematics), with a smoothed guard at rest.
//
// With v = p', a = p'', j = p''' (world frame, m/s^k) and n2 = |v|^2 + eps^2 (eps > 0):
//   v_b     = sqrt(n2)                         (speed; exact |v| for |v| >> eps)
//   a_b     = (v . a) / sqrt(n2)               (= d v_b / dt)
//   omega_b = (v x a) / n2                     (yaw rate of atan2(eta v_y, eta v_x))
//   alpha_b = (v x j) / n2 - 2 (v x a)(v . a) / n2^2   (= d omega_b / dt)
// and the wheel rates omega_{l,r} = (eta v_b -+ d_w/2 omega_b) / r_w,
//                    alpha_{l,r} = (eta a_b -+ d_w/2 alpha_b) / r_w.
//
// Why the guard: at the global start and goal the base rests (v = a = 0) and the exact
// quotients are 0/0. Their limits exist for polynomials (the heading is smooth through a rest
// instant), but evaluating them needs higher derivatives. The guard replaces |v|^2 by
// |v|^2 + eps^2, which is exact up to O(eps^2/|v|^2) wherever |v| >> eps and returns finite,
// bounded values (0 at exact rest) with finite gradients. eps = 1e-3 m/s by default: only the
// first few tens of milliseconds after a rest instant are under-weighted, where the true rates
// equal their (smooth) limits. Nothing here produces NaN for finite input.
//
// Pure functions, thread-safe, no allocation.

#include <cmath>

#include <Eigen/Core>

namespace porter::midend {

/// Body rates and their partials w.r.t. v, a, j (each a 2-vector).
struct BaseRates {
  double speed = 0.0, accel = 0.0, yaw_rate = 0.0, yaw_accel = 0.0;
  Eigen::Vector2d dspeed_dv = Eigen::Vector2d::Zero();
  Eigen::Vector2d daccel_dv = Eigen::Vector2d::Zero(), daccel_da = Eigen::Vector2d::Zero();
  Eigen::Vector2d dyaw_rate_dv = Eigen::Vector2d::Zero(), dyaw_rate_da = Eigen::Vector2d::Zero();
  Eigen::Vector2d dyaw_accel_dv = Eigen::Vector2d::Zero(), dyaw_accel_da = Eigen::Vector2d::Zero(),
                  dyaw_accel_dj = Eigen::Vector2d::Zero();
};

inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

inline BaseRates base_rates(const Eigen::Vector2d& v, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& j, double eps) {
  BaseRates r;
  const double n2 = v.squaredNorm() + eps * eps;
  const double s = std::sqrt(n2);
  const double inv_n2 = 1.0 / n2;
  const double c = cross2(v, a);     // v x a
  const double d = cross2(v, j);     // v x j
  const double e = v.dot(a);         // v . a
  const Eigen::Vector2d dc_dv(a.y(), -a.x()), dc_da(-v.y(), v.x());
  const Eigen::Vector2d dd_dv(j.y(), -j.x()), dd_dj(-v.y(), v.x());

  r.speed = s;
  r.dspeed_dv = v / s;
  r.accel = e / s;
  r.daccel_dv = a / s - (e / (n2 * s)) * v;
  r.daccel_da = v / s;
  r.yaw_rate = c * inv_n2;
  r.dyaw_rate_dv = dc_dv * inv_n2 - (2.0 * c * inv_n2 * inv_n2) * v;
  r.dyaw_rate_da = dc_da * inv_n2;
  const double inv_n4 = inv_n2 * inv_n2;
  r.yaw_accel = d * inv_n2 - 2.0 * c * e * inv_n4;
  r.dyaw_accel_dv = dd_dv * inv_n2 - (2.0 * d * inv_n4) * v - 2.0 * inv_n4 * (dc_dv * e + c * a) +
                    (8.0 * c * e * inv_n4 * inv_n2) * v;
  r.dyaw_accel_da = -2.0 * inv_n4 * (dc_da * e + c * v);
  r.dyaw_accel_dj = dd_dj * inv_n2;
  return r;
}

/// Heading phi = atan2(eta v_y, eta v_x) and its exact gradient d phi / d v =
/// (-v_y, v_x) / |v|^2, which grows like 1/|v|: callers multiply the heading's contribution by a
/// gate that vanishes like |v|^2 (see the pose residual), so the product stays bounded. At exact
/// rest returns atan2(0, 0) = 0 with a zero gradient.
inline double heading_from_velocity(const Eigen::Vector2d& v, int eta, Eigen::Vector2d* dphi_dv) {
  const double n2 = v.squaredNorm();
  *dphi_dv = n2 > 0.0 ? Eigen::Vector2d(-v.y() / n2, v.x() / n2) : Eigen::Vector2d::Zero();
  return std::atan2(eta * v.y(), eta * v.x());
}

}  // namespace porter::midend
