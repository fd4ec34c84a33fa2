// Base heading rule, base rates (v, omega, a, alpha) and wheel rates of a Trajectory, checked
// against closed forms and finite differences.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "porter/core/robot_model.hpp"
#include "porter/core/trajectory.hpp"

namespace porter {
namespace {

constexpr double kPi = 3.14159265358979323846;

Trajectory make(std::vector<TrajectoryPiece> pieces, double start_yaw_rad = 0.0) {
  TrajectoryResult r = Trajectory::create(std::move(pieces), start_yaw_rad);
  if (!r.ok()) throw std::runtime_error("unexpected failure: " + r.error);
  return std::move(*r.trajectory);
}

double angle_diff(double a, double b) { return std::remainder(a - b, 2.0 * kPi); }

// One piece whose xy is given by coefficient rows (x_k, y_k); the arm stays at zero.
TrajectoryPiece xy_piece(double T, int eta, std::vector<std::pair<double, double>> xy) {
  TrajectoryPiece p;
  p.duration_s = T;
  p.eta = eta;
  for (size_t k = 0; k < xy.size(); ++k) {
    p.coeffs(static_cast<int>(k), 0) = xy[k].first;
    p.coeffs(static_cast<int>(k), 1) = xy[k].second;
  }
  return p;
}

TrajVector xy(double x, double y) {
  TrajVector z = TrajVector::Zero();
  z[0] = x;
  z[1] = y;
  return z;
}

// Rest-to-rest quintic between two planar points; the arm joint q1 moves 0 -> arm_q1.
TrajectoryPiece rest_to_rest(double T, int eta, const TrajVector& p0, const TrajVector& p1) {
  TrajectoryPiece p;
  p.duration_s = T;
  p.eta = eta;
  const TrajVector zero = TrajVector::Zero();
  p.coeffs = quintic_hermite(p0, zero, zero, p1, zero, zero, T);
  return p;
}

TEST(TrajectoryYaw, ForwardFollowsVelocity) {
  const Trajectory traj = make({xy_piece(2.0, 1, {{1.0, -2.0}, {1.0, 1.0}})});
  const BaseMotion m = traj.base_motion(0.7);
  EXPECT_NEAR(m.yaw_rad, kPi / 4, 1e-15);
  EXPECT_NEAR(m.speed_mps, std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(m.signed_speed_mps, std::sqrt(2.0), 1e-15);
  EXPECT_EQ(m.yaw_rate_radps, 0.0);
  EXPECT_EQ(m.accel_mps2, 0.0);
  EXPECT_FALSE(m.held);
  EXPECT_EQ(m.eta, 1);
}

TEST(TrajectoryYaw, ReverseHeadsAgainstVelocity) {
  const Trajectory traj = make({xy_piece(2.0, -1, {{0.0, 0.0}, {1.0, 1.0}})});
  const BaseMotion m = traj.base_motion(0.7);
  EXPECT_NEAR(m.yaw_rad, -3 * kPi / 4, 1e-15);
  EXPECT_NEAR(m.signed_speed_mps, -std::sqrt(2.0), 1e-15);
  const TrajVector v = traj.velocity(0.7);
  // The base's x axis is anti-parallel to the velocity.
  EXPECT_NEAR(std::cos(m.yaw_rad) * v[0] + std::sin(m.yaw_rad) * v[1], -v.head<2>().norm(), 1e-14);
  // Reversing along +x is heading pi, reported as +pi (not -pi).
  const Trajectory along_x = make({xy_piece(1.0, -1, {{0.0, 0.0}, {0.5, 0.0}})});
  EXPECT_EQ(along_x.yaw_rad(0.3), kPi);
}

TEST(TrajectoryYaw, StartFromRestUsesFirstNonVanishingDerivative) {
  const double th = 0.7, c = std::cos(th), s = std::sin(th);
  // p = d t^2: accelerating from rest.
  const Trajectory acc = make({xy_piece(1.0, 1, {{0, 0}, {0, 0}, {c, s}})});
  EXPECT_NEAR(acc.yaw_rad(0.0), th, 1e-15);
  EXPECT_NEAR(acc.base_motion(0.0).accel_mps2, 2.0, 1e-15);
  // p = d t^3: velocity and acceleration vanish at t = 0, the jerk gives the direction.
  const Trajectory jerk = make({xy_piece(1.0, 1, {{0, 0}, {0, 0}, {0, 0}, {c, s}})});
  EXPECT_NEAR(jerk.yaw_rad(0.0), th, 1e-15);
  EXPECT_NEAR(jerk.yaw_rad(1e-3), th, 1e-12);
  EXPECT_FALSE(jerk.base_motion(0.0).held);
  // Same in reverse: the base backs away, its x axis points the other way.
  const Trajectory rev = make({xy_piece(1.0, -1, {{0, 0}, {0, 0}, {0, 0}, {c, s}})});
  EXPECT_NEAR(rev.yaw_rad(0.0), th - kPi, 1e-15);
  // A start with a bent path: the heading at rest is the limit of the heading while moving.
  const Trajectory bent = make({xy_piece(1.0, 1, {{0, 0}, {0, 0}, {c, s}, {-s, c}})});
  EXPECT_NEAR(bent.yaw_rad(0.0), th, 1e-15);
  EXPECT_NEAR(angle_diff(bent.yaw_rad(1e-4), bent.yaw_rad(0.0)), 0.0, 1e-3);
}

TEST(TrajectoryYaw, EndOfTrajectoryUsesLeftLimit) {
  const TrajVector a = xy(0.5, -1.0), b = xy(1.5, 1.0);
  const double heading = std::atan2(2.0, 1.0);
  for (int eta : {1, -1}) {
    const Trajectory traj = make({rest_to_rest(2.0, eta, a, b)});
    const double expect = eta > 0 ? heading : heading - kPi;
    EXPECT_NEAR(angle_diff(traj.yaw_rad(2.0), expect), 0.0, 1e-12) << eta;
    EXPECT_NEAR(angle_diff(traj.yaw_rad(7.0), expect), 0.0, 1e-12) << eta;  // clamped
    EXPECT_NEAR(angle_diff(traj.yaw_rad(2.0 - 1e-3), expect), 0.0, 1e-9) << eta;
    EXPECT_NEAR(angle_diff(traj.yaw_rad(0.0), expect), 0.0, 1e-12) << eta;
  }
  // Braking to rest with a != 0 (x = 2t - t^2): the direction it came from is -a, not +a.
  for (int eta : {1, -1}) {
    const Trajectory brake = make({xy_piece(1.0, eta, {{0, 0}, {2, 0}, {-1, 0}})});
    EXPECT_EQ(brake.velocity(1.0)[0], 0.0);
    EXPECT_EQ(brake.yaw_rad(1.0), eta > 0 ? 0.0 : kPi);
    EXPECT_EQ(brake.yaw_rad(1.5), eta > 0 ? 0.0 : kPi);
    EXPECT_NEAR(brake.base_motion(1.0).accel_mps2, -2.0, 1e-15);  // slowing down
    EXPECT_FALSE(brake.base_motion(1.0).held);
  }
}

TEST(TrajectoryYaw, CuspUsesRightLimitAndResidualVelocitySign) {
  // x = s^2, y = s^3 with s = t - 1: the base comes to rest at t = 1 and drives back out.
  // Before: moving towards -x; after: towards +x (forward both times, so the heading flips).
  const Trajectory traj = make({xy_piece(2.0, 1, {{1, -1}, {-2, 3}, {1, -3}, {0, 1}})});
  EXPECT_NEAR(traj.position(1.0).head<2>().norm(), 0.0, 1e-15);
  EXPECT_NEAR(angle_diff(traj.yaw_rad(0.99), kPi), 0.0, 0.02);
  EXPECT_NEAR(traj.yaw_rad(1.0), 0.0, 1e-15);  // at rest: where it is about to go
  EXPECT_NEAR(traj.yaw_rad(1.01), 0.0, 0.02);
  // |v| = 2e-7 < kRestSpeed_mps, but it is still approaching the rest point: heading as before.
  EXPECT_LT(traj.base_motion(1.0 - 1e-7).speed_mps, kRestSpeed_mps);
  EXPECT_NEAR(angle_diff(traj.yaw_rad(1.0 - 1e-7), kPi), 0.0, 1e-6);
  EXPECT_NEAR(traj.yaw_rad(1.0 + 1e-7), 0.0, 1e-6);
  EXPECT_NEAR(traj.base_motion(1.0 - 1e-7).accel_mps2, -2.0, 1e-6);  // slowing down
  EXPECT_NEAR(traj.base_motion(1.0 + 1e-7).accel_mps2, 2.0, 1e-6);   // speeding up
}

TEST(TrajectoryYaw, StationaryBaseHoldsHeading) {
  const double th = 2.0;
  const TrajVector p1 = xy(std::cos(th), std::sin(th));
  const TrajVector p2 = xy(std::cos(th) - 1.0, std::sin(th));
  for (int eta : {1, -1}) {
    TrajectoryPiece arm_only;  // base still at p1, joint 3 moves
    arm_only.duration_s = 1.5;
    arm_only.eta = 1;
    TrajVector q = p1;
    q[4] = 0.8;
    arm_only.coeffs = quintic_hermite(p1, TrajVector::Zero(), TrajVector::Zero(), q,
                                      TrajVector::Zero(), TrajVector::Zero(), 1.5);
    const Trajectory traj = make(
        {rest_to_rest(1.0, eta, xy(0, 0), p1), arm_only, rest_to_rest(1.0, 1, q, p2 + (q - p1))},
        0.4);
    const double expect = eta > 0 ? th : th - kPi;
    for (double t : {1.0, 1.2, 2.0, 2.5 - 1e-12}) {
      const BaseMotion m = traj.base_motion(t);
      EXPECT_TRUE(m.held) << t;
      EXPECT_NEAR(angle_diff(m.yaw_rad, expect), 0.0, 1e-12) << t << " eta " << eta;
      EXPECT_EQ(m.yaw_rate_radps, 0.0);
      EXPECT_EQ(m.yaw_accel_radps2, 0.0);
      EXPECT_EQ(m.accel_mps2, 0.0);
      EXPECT_EQ(m.speed_mps, 0.0);
    }
    EXPECT_NEAR(traj.velocity(1.75)[4], 0.8 / 1.5 * 1.875, 1e-12);  // the arm does move
    // Third piece starts from rest towards -x: right limit.
    EXPECT_NEAR(traj.yaw_rad(2.5), kPi, 1e-12);
    EXPECT_FALSE(traj.base_motion(2.5).held);
  }
}

TEST(TrajectoryYaw, NeverMovedBaseUsesStartYaw) {
  TrajectoryPiece still;
  still.duration_s = 1.0;
  still.coeffs(0, 0) = 3.0;
  still.coeffs(0, 1) = -2.0;
  still.coeffs(1, 2) = 0.5;  // the arm moves
  const Trajectory traj = make({still, xy_piece(1.0, 1, {{3, -2}, {0, 0}, {0, 1}})}, 1.25);
  EXPECT_EQ(traj.yaw_rad(0.0), 1.25);
  EXPECT_EQ(traj.yaw_rad(0.999), 1.25);
  EXPECT_TRUE(traj.base_motion(0.5).held);
  EXPECT_NEAR(traj.yaw_rad(1.0), kPi / 2, 1e-15);
  // start_yaw_rad outside (-pi, pi] is reported wrapped.
  const Trajectory wrapped = make({still}, 7.0);
  EXPECT_NEAR(wrapped.yaw_rad(0.5), 7.0 - 2 * kPi, 1e-15);
  EXPECT_DOUBLE_EQ(wrapped.start_yaw_rad(), 7.0);
}

// A curvy multi-piece trajectory with forward and reverse pieces and non-zero speed everywhere.
Trajectory curvy() {
  std::vector<TrajectoryPiece> pieces;
  const double T[4] = {0.8, 1.1, 0.7, 1.3};
  auto p = [](double t) {
    return xy(std::sin(1.3 * t) + 2.0 * t, 0.8 * std::cos(0.9 * t) + 0.3 * t * t);
  };
  auto v = [](double t) {
    return xy(1.3 * std::cos(1.3 * t) + 2.0, -0.72 * std::sin(0.9 * t) + 0.6 * t);
  };
  auto a = [](double t) { return xy(-1.69 * std::sin(1.3 * t), -0.648 * std::cos(0.9 * t) + 0.6); };
  double t0 = 0.0;
  for (int i = 0; i < 4; ++i) {
    TrajectoryPiece piece;
    piece.duration_s = T[i];
    piece.eta = (i == 2) ? -1 : 1;
    piece.coeffs =
        quintic_hermite(p(t0), v(t0), a(t0), p(t0 + T[i]), v(t0 + T[i]), a(t0 + T[i]), T[i]);
    pieces.push_back(piece);
    t0 += T[i];
  }
  return make(pieces);
}

TEST(TrajectoryBaseRates, MatchFiniteDifferences) {
  const Trajectory traj = curvy();
  const double h = 1e-5;
  int checked = 0;
  for (double t = 0.01; t < traj.total_duration_s() - 0.01; t += 0.037) {
    double tau = 0.0;
    const int i = traj.locate(t, &tau);
    if (tau < 2 * h || tau > traj.piece(i).duration_s - 2 * h) continue;  // stay inside a piece
    const BaseMotion m = traj.base_motion(t);
    const BaseMotion mp = traj.base_motion(t + h), mm = traj.base_motion(t - h);
    const Eigen::Vector2d dp = (traj.position(t + h) - traj.position(t - h)).head<2>() / (2 * h);
    ASSERT_GT(m.speed_mps, 0.1);
    EXPECT_NEAR(m.speed_mps, dp.norm(), 1e-7) << t;
    EXPECT_NEAR(m.signed_speed_mps,
                dp.dot(Eigen::Vector2d(std::cos(m.yaw_rad), std::sin(m.yaw_rad))), 1e-7)
        << t;
    EXPECT_NEAR(m.yaw_rate_radps, angle_diff(mp.yaw_rad, mm.yaw_rad) / (2 * h), 1e-6) << t;
    EXPECT_NEAR(m.accel_mps2, (mp.speed_mps - mm.speed_mps) / (2 * h), 1e-6) << t;
    EXPECT_NEAR(m.yaw_accel_radps2, (mp.yaw_rate_radps - mm.yaw_rate_radps) / (2 * h), 1e-6) << t;
    EXPECT_EQ(m.eta, traj.piece(i).eta);
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(TrajectoryBaseRates, RestLimitsAreContinuous) {
  // x = s^2, y = s^2 / 2 + s^3 + s^4 with s = t - 1: a cusp at t = 1 on a bent path. omega, alpha
  // at the rest instant equal the limits of the regular formulas from both sides.
  const Trajectory traj = make({xy_piece(2.0, 1, {{1, 0.5}, {-2, -2}, {1, 3.5}, {0, -3}, {0, 1}})});
  EXPECT_LT(traj.base_motion(1.0).speed_mps, 1e-14);
  const BaseMotion m0 = traj.base_motion(1.0);
  // h balances truncation (O(h^2)) against rounding near rest (O(eps / h^3)).
  const double h = 1e-3;
  const BaseMotion mp = traj.base_motion(1.0 + h), mm = traj.base_motion(1.0 - h);
  ASSERT_GT(mp.speed_mps, kRestSpeed_mps);
  ASSERT_GT(mm.speed_mps, kRestSpeed_mps);
  EXPECT_GT(std::abs(m0.yaw_rate_radps), 0.1);
  EXPECT_NEAR(m0.yaw_rate_radps, 0.5 * (mp.yaw_rate_radps + mm.yaw_rate_radps), 2e-5);
  EXPECT_NEAR(m0.yaw_accel_radps2, (mp.yaw_rate_radps - mm.yaw_rate_radps) / (2 * h), 2e-5);
  EXPECT_GT(std::abs(m0.yaw_accel_radps2), 0.1);
  // And just inside the rest threshold.
  const BaseMotion mn = traj.base_motion(1.0 + 1e-6);
  EXPECT_NEAR(mn.yaw_rate_radps, m0.yaw_rate_radps, 1e-4);
  // Start from rest with k = 2: omega -> cross(a, j) / (2 |a|^2) = 1.5 for p = (t^2, t^3).
  const Trajectory start = make({xy_piece(1.0, 1, {{0, 0}, {0, 0}, {1, 0}, {0, 1}})});
  EXPECT_NEAR(start.base_motion(0.0).yaw_rate_radps, 1.5, 1e-15);
  EXPECT_NEAR(start.base_motion(0.0).yaw_accel_radps2, 0.0, 1e-15);
  EXPECT_NEAR(start.base_motion(1e-3).yaw_rate_radps, 6.0 / (4.0 + 9e-6), 1e-12);
}

// Near a rest instant: q(s) = (a s^3 + e s^5, c s^3 + b s^4) has dq/ds = s^2 W(s) with
// W = (3a + 5e s^2, 3c + 4b s), so the exact rates are closed forms in W, W' = (10 e s, 4 b),
// W'' = (10 e, 0): omega = (W x W')/|W|^2, alpha = (W x W'')/|W|^2 - 2 (W x W')(W . W')/|W|^4,
// v = s^2 |W|, dv/ds = 2 s |W| + s^2 (W . W')/|W|. Evaluated in long double as the reference.
struct RestReference {
  long double yaw, speed, dspeed, omega, alpha;
};
constexpr long double kA = 0.6L, kB = -0.9L, kC = 0.2L, kE = 0.35L;
RestReference rest_reference(long double s) {
  const long double wx = 3 * kA + 5 * kE * s * s, wy = 3 * kC + 4 * kB * s;
  const long double w1x = 10 * kE * s, w1y = 4 * kB;
  const long double w2x = 10 * kE, w2y = 0;
  const long double n2 = wx * wx + wy * wy, n = std::sqrt(n2);
  const long double c1 = wx * w1y - wy * w1x, d1 = wx * w1x + wy * w1y;
  RestReference r;
  r.yaw = std::atan2(wy, wx);
  r.speed = s * s * n;
  r.dspeed = 2 * s * n + s * s * d1 / n;
  r.omega = c1 / n2;
  r.alpha = (wx * w2y - wy * w2x) / n2 - 2 * c1 * d1 / (n2 * n2);
  return r;
}

void expect_rel(double value, long double reference, double tol, const char* what, double h) {
  EXPECT_LE(std::abs(value - static_cast<double>(reference)),
            tol * std::max(1e-300L, std::abs(reference)))
      << what << " at " << h << " s from rest: " << value << " vs " << static_cast<double>(reference);
}

TEST(TrajectoryNearRest, StartMatchesHighPrecisionReference) {
  // p(t) = q(t): the rest instant is t = 0 and the coefficients are exact.
  const Trajectory traj = make({xy_piece(1.0, 1, {{0, 0}, {0, 0}, {0, 0}, {0.6, 0.2}, {0, -0.9}, {0.35, 0}})});
  for (const double h : {1e-3, 1e-4, 1e-5, 1e-6}) {
    const BaseMotion m = traj.base_motion(h);
    const RestReference r = rest_reference(h);
    EXPECT_NEAR(angle_diff(m.yaw_rad, static_cast<double>(r.yaw)), 0.0, 1e-12) << h;
    expect_rel(m.speed_mps, r.speed, 1e-12, "speed", h);
    expect_rel(m.accel_mps2, r.dspeed, 1e-12, "a_b", h);
    expect_rel(m.yaw_rate_radps, r.omega, 1e-12, "omega_b", h);
    expect_rel(m.yaw_accel_radps2, r.alpha, 1e-12, "alpha_b", h);
  }
}

TEST(TrajectoryNearRest, GoalMatchesHighPrecisionReference) {
  // p(tau) = q(T - tau) expanded in tau in double: the rest instant is the end of the piece and
  // pd, pdd there are rounding residuals, as in a real mid-end trajectory.
  const double T = 1.3;
  const double qx[6] = {0, 0, 0, 0.6, 0, 0.35}, qy[6] = {0, 0, 0, 0.2, -0.9, 0};
  std::vector<std::pair<double, double>> rows(6, {0.0, 0.0});
  for (int n = 0; n < 6; ++n) {      // q_n (T - tau)^n = q_n sum_k C(n, k) T^(n-k) (-tau)^k
    double binom = 1.0;
    for (int k = 0; k <= n; ++k) {
      const double f = binom * std::pow(T, n - k) * ((k % 2) ? -1.0 : 1.0);
      rows[static_cast<size_t>(k)].first += qx[n] * f;
      rows[static_cast<size_t>(k)].second += qy[n] * f;
      binom = binom * (n - k) / (k + 1);
    }
  }
  for (const int eta : {1, -1}) {
    const Trajectory traj = make({xy_piece(T, eta, rows)});
    EXPECT_LT(traj.velocity(T).head<2>().norm(), kRestSpeed_mps);
    for (const double h : {1e-3, 1e-4, 1e-5}) {
      const BaseMotion m = traj.base_motion(T - h);
      const RestReference r = rest_reference(h);
      // dp/dtau = -dq/ds: heading flipped, omega negated, alpha kept, speed decreasing.
      const double yaw = static_cast<double>(r.yaw) + kPi + (eta < 0 ? kPi : 0.0);
      EXPECT_NEAR(angle_diff(m.yaw_rad, yaw), 0.0, 1e-9) << h;
      expect_rel(m.speed_mps, r.speed, 1e-9, "speed", h);
      expect_rel(m.accel_mps2, -r.dspeed, 1e-9, "a_b", h);
      expect_rel(m.yaw_rate_radps, -r.omega, 1e-9, "omega_b", h);
      expect_rel(m.yaw_accel_radps2, r.alpha, 1e-9, "alpha_b", h);
      // The wheels see the same rates.
      const WheelRates w = traj.wheel_rates(T - h, 0.4, 0.1);
      EXPECT_NEAR(w.right_radps2 - w.left_radps2, 0.4 * m.yaw_accel_radps2 / 0.1, 1e-9);
    }
  }
}

TEST(TrajectoryNearRest, SwitchToTheExpansionIsContinuous) {
  // Just below and just above kSlowSpeed_mps the two evaluations agree with the reference.
  const Trajectory traj = make({xy_piece(1.0, 1, {{0, 0}, {0, 0}, {0, 0}, {0.6, 0.2}, {0, -0.9}, {0.35, 0}})});
  double lo = 1e-4, hi = 0.5;  // bisect for the time at which the speed crosses kSlowSpeed_mps
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (traj.velocity(mid).head<2>().norm() < kSlowSpeed_mps ? lo : hi) = mid;
  }
  for (const double t : {lo - 1e-9, hi + 1e-9}) {
    const BaseMotion m = traj.base_motion(t);
    const RestReference r = rest_reference(t);
    expect_rel(m.yaw_rate_radps, r.omega, 1e-10, "omega_b", t);
    expect_rel(m.yaw_accel_radps2, r.alpha, 1e-9, "alpha_b", t);
    expect_rel(m.accel_mps2, r.dspeed, 1e-10, "a_b", t);
  }
}

TEST(TrajectoryWheels, MatchDiffDriveKinematics) {
  const Trajectory traj = curvy();
  const double d_w = 0.45, r_w = 0.08;
  const double h = 1e-5;
  for (double t = 0.05; t < traj.total_duration_s(); t += 0.11) {
    double tau = 0.0;
    const int i = traj.locate(t, &tau);
    if (tau < 2 * h || tau > traj.piece(i).duration_s - 2 * h) continue;
    const WheelRates w = traj.wheel_rates(t, d_w, r_w);
    // Each wheel's ground speed from finite differences of the pose: v -/+ (d_w / 2) omega.
    auto wheel_fd = [&](double tc) {
      const BaseMotion m = traj.base_motion(tc);
      const Eigen::Vector2d dp =
          (traj.position(tc + h) - traj.position(tc - h)).head<2>() / (2 * h);
      const double v = dp.dot(Eigen::Vector2d(std::cos(m.yaw_rad), std::sin(m.yaw_rad)));
      const double om = angle_diff(traj.yaw_rad(tc + h), traj.yaw_rad(tc - h)) / (2 * h);
      return Eigen::Vector2d((v - 0.5 * d_w * om) / r_w, (v + 0.5 * d_w * om) / r_w);
    };
    const Eigen::Vector2d fd = wheel_fd(t);
    EXPECT_NEAR(w.left_radps, fd[0], 1e-5) << t;
    EXPECT_NEAR(w.right_radps, fd[1], 1e-5) << t;
    const WheelRates wp = traj.wheel_rates(t + h, d_w, r_w), wm = traj.wheel_rates(t - h, d_w, r_w);
    EXPECT_NEAR(w.left_radps2, (wp.left_radps - wm.left_radps) / (2 * h), 1e-4) << t;
    EXPECT_NEAR(w.right_radps2, (wp.right_radps - wm.right_radps) / (2 * h), 1e-4) << t;
  }
}

TEST(TrajectoryWheels, SampleCollectsEverything) {
  const Trajectory traj = curvy();
  BaseLimits limits;
  limits.track_width_m = 0.45;
  limits.wheel_radius_m = 0.08;
  for (double t : {-1.0, 0.0, 0.5, 1.9, 2.4, traj.total_duration_s(), 10.0}) {
    const TrajectoryState s = traj.sample(t, limits);
    const double tc = std::min(std::max(t, 0.0), traj.total_duration_s());
    EXPECT_EQ(s.t_s, tc);
    double tau = 0.0;
    EXPECT_EQ(s.piece, traj.locate(t, &tau));
    EXPECT_EQ(s.z, traj.position(t));
    EXPECT_EQ(s.z_dot, traj.velocity(t));
    EXPECT_EQ(s.z_ddot, traj.acceleration(t));
    const BaseMotion m = traj.base_motion(t);
    EXPECT_EQ(s.base.yaw_rad, m.yaw_rad);
    EXPECT_EQ(s.base.yaw_rate_radps, m.yaw_rate_radps);
    const WheelRates w = wheel_rates(m, 0.45, 0.08);
    EXPECT_EQ(s.wheels.left_radps, w.left_radps);
    EXPECT_EQ(s.wheels.right_radps2, w.right_radps2);
  }
  // Straight reverse: both wheels turn backwards at v / r.
  BaseMotion rev;
  rev.eta = -1;
  rev.speed_mps = 0.4;
  rev.accel_mps2 = 0.2;
  const WheelRates w = wheel_rates(rev, 0.45, 0.08);
  EXPECT_DOUBLE_EQ(w.left_radps, -5.0);
  EXPECT_DOUBLE_EQ(w.right_radps, -5.0);
  EXPECT_DOUBLE_EQ(w.left_radps2, -2.5);
  // Turning on the spot to the left: left wheel backwards, right forwards.
  BaseMotion spin;
  spin.yaw_rate_radps = 1.0;
  spin.yaw_accel_radps2 = -2.0;
  const WheelRates ws = wheel_rates(spin, 0.4, 0.1);
  EXPECT_DOUBLE_EQ(ws.left_radps, -2.0);
  EXPECT_DOUBLE_EQ(ws.right_radps, 2.0);
  EXPECT_DOUBLE_EQ(ws.left_radps2, 4.0);
}

}  // namespace
}  // namespace porter
