// The base tracking law: closed-loop convergence of a simulated unicycle on a straight line, a
// turn and reverse segments; feed-forward alone reproduces the reference; the wheel speed and
// acceleration limits hold; the Lyapunov derivative is non-positive for either driving direction.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "porter/tracker/control_law.hpp"
#include "trajectory_fixtures.hpp"

namespace porter::tracker {
namespace {

using test::scout_limits;

// A unicycle driven by the law at 100 Hz (zero-order hold, integrated in 0.5 ms steps).
struct ClosedLoop {
  double initial_position_error_m = 0.0;
  double late_position_error_m = 0.0;  ///< max after settle_s
  double late_yaw_error_rad = 0.0;     ///< max after settle_s
  double max_wheel_radps = 0.0;
  double max_wheel_step_radps = 0.0;   ///< largest change of a wheel speed between commands
  double max_command_jump_mps = 0.0;
};

BaseReference reference_at(const Trajectory& traj, double t) {
  const TrajectoryState s = traj.sample(t, scout_limits());
  return {{s.z[0], s.z[1], s.base.yaw_rad}, s.base.signed_speed_mps, s.base.yaw_rate_radps};
}

// start_moving: the previous command is the reference's feed-forward at t = 0 (the base is
// already moving), else zero (the base starts at rest and the acceleration limit applies).
ClosedLoop simulate(const Trajectory& traj, BasePose start, const TrackingGains& gains,
                    double settle_s, bool start_moving = false,
                    const BaseLimits& limits = scout_limits()) {
  ClosedLoop r;
  BasePose pose = start;
  BaseCommand previous;
  if (start_moving) {
    const BaseReference ref = reference_at(traj, 0.0);
    previous = {ref.v_mps, ref.omega_radps};
  }
  const double dt = 0.01;
  const double half = 0.5 * limits.track_width_m;
  for (double t = 0.0; t <= traj.total_duration_s() + 1e-9; t += dt) {
    const BaseReference ref = reference_at(traj, t);
    const BaseControl c = base_control(ref, pose, previous, dt, gains, limits);
    const PoseError e = error_in_reference_frame(ref.pose, pose);
    const double pos_err = std::hypot(e.x_m, e.y_m);
    if (t == 0.0) r.initial_position_error_m = pos_err;
    if (t >= settle_s) {
      r.late_position_error_m = std::max(r.late_position_error_m, pos_err);
      r.late_yaw_error_rad = std::max(r.late_yaw_error_rad, std::abs(e.yaw_rad));
    }
    const BaseCommand& cmd = c.limited.command;
    const double wl = (cmd.v_mps - half * cmd.omega_radps) / limits.wheel_radius_m;
    const double wr = (cmd.v_mps + half * cmd.omega_radps) / limits.wheel_radius_m;
    const double pl = (previous.v_mps - half * previous.omega_radps) / limits.wheel_radius_m;
    const double pr = (previous.v_mps + half * previous.omega_radps) / limits.wheel_radius_m;
    r.max_wheel_radps = std::max({r.max_wheel_radps, std::abs(wl), std::abs(wr)});
    r.max_wheel_step_radps =
        std::max({r.max_wheel_step_radps, std::abs(wl - pl), std::abs(wr - pr)});
    r.max_command_jump_mps = std::max(r.max_command_jump_mps, std::abs(cmd.v_mps - previous.v_mps));
    previous = cmd;
    for (int k = 0; k < 20; ++k) {
      const double h = dt / 20;
      pose.x_m += cmd.v_mps * std::cos(pose.yaw_rad) * h;
      pose.y_m += cmd.v_mps * std::sin(pose.yaw_rad) * h;
      pose.yaw_rad = wrap_angle(pose.yaw_rad + cmd.omega_radps * h);
    }
  }
  return r;
}

BasePose offset(const Trajectory& traj, double along_m, double cross_m, double yaw_rad) {
  const BaseReference ref = reference_at(traj, 0.0);
  const double c = std::cos(ref.pose.yaw_rad), s = std::sin(ref.pose.yaw_rad);
  return {ref.pose.x_m + c * along_m - s * cross_m, ref.pose.y_m + s * along_m + c * cross_m,
          ref.pose.yaw_rad + yaw_rad};
}

// Errors after the settling time: below 2 cm / 0.02 rad and a tenth of the initial error.
void expect_converged(const ClosedLoop& r) {
  EXPECT_LT(r.late_position_error_m, 0.02);
  EXPECT_LT(r.late_position_error_m, 0.1 * r.initial_position_error_m);
  EXPECT_LT(r.late_yaw_error_rad, 0.02);
}

void expect_within_limits(const ClosedLoop& r) {
  const BaseLimits limits = scout_limits();
  EXPECT_LE(r.max_wheel_radps, limits.wheel_omega_max_radps + 1e-9);
  EXPECT_LE(r.max_wheel_step_radps, limits.wheel_alpha_max_radps2 * 0.01 + 1e-9);
}

TEST(TrackingLaw, ConvergesOnStraightLine) {
  const Trajectory traj = test::straight(0.5, 8.0, +1);
  const ClosedLoop r = simulate(traj, offset(traj, -0.15, 0.2, 0.2), TrackingGains{}, 6.0);
  EXPECT_GT(r.initial_position_error_m, 0.2);
  expect_converged(r);
  expect_within_limits(r);
}

TEST(TrackingLaw, ConvergesOnTurn) {
  const Trajectory traj = test::arc(0.4, 1.0, 12.0, +1);
  const ClosedLoop r = simulate(traj, offset(traj, 0.1, -0.2, -0.25), TrackingGains{}, 7.0);
  expect_converged(r);
  expect_within_limits(r);
}

TEST(TrackingLaw, ConvergesInReverse) {
  const Trajectory traj = test::straight(0.4, 8.0, -1, 0.3);
  ASSERT_LT(reference_at(traj, 3.0).v_mps, 0.0);
  const ClosedLoop r = simulate(traj, offset(traj, 0.1, 0.2, -0.2), TrackingGains{}, 8.0);
  expect_converged(r);
  expect_within_limits(r);
}

TEST(TrackingLaw, ConvergesOnReverseTurn) {
  const Trajectory traj = test::arc(0.3, 1.2, 14.0, -1);
  ASSERT_LT(reference_at(traj, 3.0).v_mps, 0.0);
  const ClosedLoop r = simulate(traj, offset(traj, -0.1, -0.15, 0.2), TrackingGains{}, 9.0);
  expect_converged(r);
  expect_within_limits(r);
}

TEST(TrackingLaw, ReverseDivergesWithKanayamasOriginalHeadingTerm) {
  // The law's |v_r| is what makes reverse work: with k_yaw multiplying v_r itself (Kanayama's
  // original form), the same reverse start does not converge. Emulated by a negative k_yaw_1pm
  // on a path that is entirely reverse (v_r < 0, so k_yaw |v_r| = -k_yaw v_r).
  const Trajectory traj = test::arc(0.3, 1.2, 14.0, -1);
  TrackingGains original;
  original.k_yaw_1pm = -original.k_yaw_1pm;
  original.k_yaw_rest_1ps = 0.0;
  const ClosedLoop r = simulate(traj, offset(traj, -0.1, -0.15, 0.2), original, 8.0);
  EXPECT_GT(r.late_position_error_m, 0.05);
}

TEST(TrackingLaw, FeedForwardAloneReproducesReference) {
  TrackingGains none;
  none.k_x_1ps = none.k_y_1pm2 = none.k_yaw_1pm = none.k_yaw_rest_1ps = 0.0;
  for (const Trajectory& traj : {test::straight(0.5, 4.0, +1), test::arc(0.4, 1.0, 8.0, +1),
                                 test::straight(0.4, 4.0, -1, -1.0), test::arc(0.3, 1.5, 8.0, -1)}) {
    const ClosedLoop r = simulate(traj, offset(traj, 0, 0, 0), none, 0.0, true);
    // Zero-order hold of a smooth reference over 10 ms: millimetre-level drift at most.
    EXPECT_LT(r.late_position_error_m, 5e-3);
    EXPECT_LT(r.late_yaw_error_rad, 5e-3);
  }
}

TEST(TrackingLaw, ZeroErrorGivesFeedForward) {
  const BaseReference ref{{1.0, -2.0, 0.7}, -0.35, 0.2};
  const BaseCommand c = tracking_law(ref, ref.pose, TrackingGains{});
  EXPECT_DOUBLE_EQ(c.v_mps, -0.35);
  EXPECT_DOUBLE_EQ(c.omega_radps, 0.2);
}

TEST(TrackingLaw, LyapunovDerivativeNonPositiveBothDirections) {
  // dV/dt = e_x (v_r cos e_yaw - v) + e_y v_r sin e_yaw + sin(e_yaw) (omega_r - omega) / k_y
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const TrackingGains g;
  for (int i = 0; i < 10000; ++i) {
    const BasePose measured{u(rng), u(rng), 3.0 * u(rng)};
    const BaseReference ref{{u(rng), u(rng), 3.0 * u(rng)}, u(rng), u(rng)};
    const PoseError e = error_in_measured_frame(ref.pose, measured);
    const BaseCommand c = tracking_law(ref, measured, g);
    const double vdot = e.x_m * (ref.v_mps * std::cos(e.yaw_rad) - c.v_mps) +
                        e.y_m * ref.v_mps * std::sin(e.yaw_rad) +
                        std::sin(e.yaw_rad) * (ref.omega_radps - c.omega_radps) / g.k_y_1pm2;
    const double expected = -g.k_x_1ps * e.x_m * e.x_m -
                            (g.k_yaw_1pm * std::abs(ref.v_mps) + g.k_yaw_rest_1ps) *
                                std::pow(std::sin(e.yaw_rad), 2) / g.k_y_1pm2;
    ASSERT_NEAR(vdot, expected, 1e-12);
    ASSERT_LE(vdot, 1e-15);
  }
}

TEST(TrackingLaw, ErrorFrames) {
  const BasePose ref{1.0, 1.0, 0.5 * M_PI};  // facing +y
  const BasePose measured{0.0, 0.0, 0.0};    // facing +x
  const PoseError in_measured = error_in_measured_frame(ref, measured);
  EXPECT_NEAR(in_measured.x_m, 1.0, 1e-15);
  EXPECT_NEAR(in_measured.y_m, 1.0, 1e-15);
  EXPECT_NEAR(in_measured.yaw_rad, 0.5 * M_PI, 1e-15);
  const PoseError in_ref = error_in_reference_frame(ref, measured);
  EXPECT_NEAR(in_ref.x_m, 1.0, 1e-15);   // along +y
  EXPECT_NEAR(in_ref.y_m, -1.0, 1e-15);  // along -x
  EXPECT_NEAR(wrap_angle(M_PI + 0.1), -M_PI + 0.1, 1e-15);
  EXPECT_EQ(wrap_angle(-M_PI), M_PI);
}

TEST(WheelLimits, SpeedLimitKeepsCurvature) {
  const BaseLimits limits = scout_limits();
  const BaseCommand big{3.0, 4.0};
  const LimitedCommand r = limit_command(big, {}, 100.0, limits);  // long dt: no accel cut
  EXPECT_TRUE(r.speed_limited);
  const double half = 0.5 * limits.track_width_m;
  const double wr = (r.command.v_mps + half * r.command.omega_radps) / limits.wheel_radius_m;
  EXPECT_NEAR(std::abs(wr), limits.wheel_omega_max_radps, 1e-9);
  EXPECT_NEAR(r.command.omega_radps / r.command.v_mps, 4.0 / 3.0, 1e-12);
}

TEST(WheelLimits, AccelerationLimitBoundsTheChange) {
  const BaseLimits limits = scout_limits();
  const LimitedCommand r = limit_command({0.8, 0.0}, {0.0, 0.0}, 0.01, limits);
  EXPECT_TRUE(r.accel_limited);
  EXPECT_FALSE(r.speed_limited);
  EXPECT_NEAR(r.command.v_mps, limits.wheel_alpha_max_radps2 * 0.01 * limits.wheel_radius_m, 1e-12);
  EXPECT_NEAR(r.command.omega_radps, 0.0, 1e-12);
}

TEST(WheelLimits, WithinLimitsUnchanged) {
  const LimitedCommand r = limit_command({0.30, 0.2}, {0.29, 0.2}, 0.01, scout_limits());
  EXPECT_FALSE(r.speed_limited);
  EXPECT_FALSE(r.accel_limited);
  EXPECT_DOUBLE_EQ(r.command.v_mps, 0.30);
  EXPECT_NEAR(r.command.omega_radps, 0.2, 1e-12);
}

TEST(WheelLimits, RandomCommandsStayInsideTheBox) {
  const BaseLimits limits = scout_limits();
  const double half = 0.5 * limits.track_width_m;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  BaseCommand previous;
  for (int i = 0; i < 20000; ++i) {
    const LimitedCommand r = limit_command({u(rng), u(rng)}, previous, 0.01, limits);
    const auto wheels = [&](const BaseCommand& c) {
      return std::pair{(c.v_mps - half * c.omega_radps) / limits.wheel_radius_m,
                       (c.v_mps + half * c.omega_radps) / limits.wheel_radius_m};
    };
    const auto [wl, wr] = wheels(r.command);
    const auto [pl, pr] = wheels(previous);
    ASSERT_LE(std::max(std::abs(wl), std::abs(wr)), limits.wheel_omega_max_radps + 1e-9);
    ASSERT_LE(std::max(std::abs(wl - pl), std::abs(wr - pr)),
              limits.wheel_alpha_max_radps2 * 0.01 + 1e-9);
    previous = r.command;
  }
}

TEST(WheelLimits, NonFiniteGivesZero) {
  const LimitedCommand r = limit_command({std::nan(""), 0.0}, {0.5, 0.0}, 0.01, scout_limits());
  EXPECT_TRUE(r.non_finite);
  EXPECT_EQ(r.command.v_mps, 0.0);
  EXPECT_EQ(r.command.omega_radps, 0.0);
}

}  // namespace
}  // namespace porter::tracker
