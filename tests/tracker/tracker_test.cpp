// The tracker's loop logic, stepped with explicit time: staleness of the state and of the
// trajectory, hold at the end, hand-off between trajectories, refusals, e-stop latching and
// release, and the tracking-error fault.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "porter/tracker/tracker.hpp"
#include "trajectory_fixtures.hpp"

namespace porter::tracker {
namespace {

constexpr std::int64_t kT0 = 1'700'000'000'000'000;  // an arbitrary wall-clock utime
constexpr std::int64_t kPeriod = 10'000;              // 10 ms

TrackerParams params() {
  TrackerParams p;
  p.base_limits = test::scout_limits();
  p.joint_velocity_max_radps = JointVector::Constant(1.0);
  return p;
}

TrajectoryOffer offer(const Trajectory& traj, std::int64_t start_utime, std::int64_t plan_id = 1,
                      std::int64_t utime = 0) {
  return {traj, utime == 0 ? start_utime : utime, start_utime, plan_id, "world"};
}

MeasuredState state_at(const BasePose& pose) {
  MeasuredState s;
  s.pose = pose;
  s.pose_valid = s.base_valid = s.arm_valid = true;
  s.num_joints = kNumArmJoints;
  return s;
}

// Drives a Tracker with a simulated unicycle that obeys its commands perfectly.
struct Rig {
  Tracker tracker{params()};
  BasePose pose;
  std::int64_t now = kT0;
  bool feed_state = true;

  const TrackerOutput& step() {
    if (feed_state) tracker.on_state(state_at(pose), now);
    const TrackerOutput& out = tracker.step(now);
    if (out.base_enabled) {
      for (int k = 0; k < 10; ++k) {
        const double h = 0.001;
        pose.x_m += out.base.v_mps * std::cos(pose.yaw_rad) * h;
        pose.y_m += out.base.v_mps * std::sin(pose.yaw_rad) * h;
        pose.yaw_rad += out.base.omega_radps * h;
      }
    }
    now += kPeriod;
    return out;
  }
  void run_for(double seconds) {
    for (int i = 0; i < static_cast<int>(std::lround(seconds * 100)); ++i) step();
  }
};

void expect_zero(const TrackerOutput& out) {
  EXPECT_FALSE(out.base_enabled);
  EXPECT_EQ(out.base.v_mps, 0.0);
  EXPECT_EQ(out.base.omega_radps, 0.0);
  EXPECT_FALSE(out.arm_enabled);
}

TEST(Tracker, IdleWithoutTrajectory) {
  Rig rig;
  const TrackerOutput& out = rig.step();
  EXPECT_EQ(out.state, TrackerState::idle);
  EXPECT_TRUE(out.state_changed);
  expect_zero(out);
  EXPECT_FALSE(rig.step().state_changed);
}

TEST(Tracker, TracksAndHoldsAtTheEnd) {
  Rig rig;
  const Trajectory traj = test::straight(0.5, 1.0, +1);
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(traj, rig.now), rig.now).accepted);
  const TrackerOutput& first = rig.step();
  EXPECT_EQ(first.state, TrackerState::tracking);
  EXPECT_TRUE(first.base_enabled);
  EXPECT_TRUE(first.arm_enabled);
  rig.run_for(1.5);
  EXPECT_GT(rig.step().base.v_mps, 0.3);
  rig.run_for(traj.total_duration_s());
  const TrackerOutput& end = rig.step();
  EXPECT_EQ(end.state, TrackerState::finished);
  EXPECT_TRUE(end.base_enabled);
  EXPECT_EQ(end.base.v_mps, 0.0);
  EXPECT_EQ(end.base.omega_radps, 0.0);
  EXPECT_TRUE(end.arm_enabled);
  const TrajVector final_z = traj.position(traj.total_duration_s());
  for (int j = 0; j < kNumArmJoints; ++j) EXPECT_DOUBLE_EQ(end.q_rad[j], final_z[2 + j]);
  EXPECT_TRUE(end.qd_radps.isZero());
  EXPECT_NEAR(rig.pose.x_m, final_z[0], 0.01);
  // Holding: stays FINISHED.
  rig.run_for(1.0);
  EXPECT_EQ(rig.step().state, TrackerState::finished);
}

TEST(Tracker, StaleStateGivesZeroCommandsAndResumes) {
  Rig rig;
  const Trajectory traj = test::straight(0.3, 6.0, +1);
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(traj, rig.now), rig.now).accepted);
  rig.run_for(2.0);
  EXPECT_EQ(rig.step().state, TrackerState::tracking);
  rig.feed_state = false;
  rig.run_for(0.09);  // the next step sees a state exactly at the limit: still usable
  EXPECT_EQ(rig.step().state, TrackerState::tracking);
  const TrackerOutput& stale = rig.step();
  EXPECT_EQ(stale.state, TrackerState::stale_state);
  EXPECT_NE(stale.message.find("ROBOT_STATE is"), std::string::npos);
  expect_zero(stale);
  rig.feed_state = true;
  EXPECT_EQ(rig.step().state, TrackerState::tracking);
}

TEST(Tracker, InvalidStateFlagsGiveZeroCommands) {
  for (int flag = 0; flag < 4; ++flag) {
    Tracker tracker(params());
    ASSERT_TRUE(tracker.on_trajectory(offer(test::straight(0.3, 2.0, +1), kT0), kT0).accepted);
    MeasuredState s = state_at({});
    if (flag == 0) s.pose_valid = false;
    if (flag == 1) s.base_valid = false;
    if (flag == 2) s.arm_valid = false;
    if (flag == 3) s.num_joints = 5;
    tracker.on_state(s, kT0);
    const TrackerOutput& out = tracker.step(kT0 + kPeriod);
    EXPECT_EQ(out.state, TrackerState::stale_state) << flag;
    expect_zero(out);
  }
  // Without require_arm_state the arm does not matter.
  TrackerParams p = params();
  p.require_arm_state = false;
  Tracker tracker(p);
  ASSERT_TRUE(tracker.on_trajectory(offer(test::straight(0.3, 2.0, +1), kT0), kT0).accepted);
  MeasuredState s = state_at({});
  s.arm_valid = false;
  s.num_joints = 0;
  tracker.on_state(s, kT0);
  EXPECT_EQ(tracker.step(kT0 + kPeriod).state, TrackerState::tracking);
}

TEST(Tracker, StaleTrajectoryWhenTimeoutConfigured) {
  TrackerParams p = params();
  p.trajectory_timeout_s = 0.5;
  Rig rig{Tracker(p), {}};
  const Trajectory traj = test::straight(0.3, 6.0, +1);
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(traj, rig.now, 1), rig.now).accepted);
  rig.run_for(0.5);
  EXPECT_EQ(rig.step().state, TrackerState::tracking);  // 0.5 s: at the limit
  EXPECT_EQ(rig.step().state, TrackerState::stale_trajectory);
  expect_zero(rig.tracker.output());
  // The planner publishing the same plan again (start in the past, within the lag) resumes it.
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(traj, rig.now - 100'000, 1, rig.now), rig.now).accepted);
  EXPECT_EQ(rig.step().state, TrackerState::tracking);
}

TEST(Tracker, TrajectoryDoesNotGoStaleWithoutTimeout) {
  Rig rig;  // trajectory_timeout_s = 0
  const Trajectory traj = test::straight(0.3, 3.0, +1);
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(traj, rig.now), rig.now).accepted);
  rig.run_for(4.0);
  EXPECT_EQ(rig.step().state, TrackerState::tracking);
}

TEST(Tracker, RefusesWrongFrameOldMessageAndLateStart) {
  Tracker tracker(params());
  const Trajectory traj = test::straight(0.3, 1.0, +1);
  TrajectoryOffer wrong_frame = offer(traj, kT0, 1);
  wrong_frame.frame_id = "odom";
  OfferResult r = tracker.on_trajectory(wrong_frame, kT0);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.reason.find("frame 'odom'"), std::string::npos);
  r = tracker.on_trajectory(offer(traj, kT0 + 2'000'000, 2, kT0 - 1'500'000), kT0);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.reason.find("old"), std::string::npos);
  r = tracker.on_trajectory(offer(traj, kT0 - 300'000, 3, kT0), kT0);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.reason.find("in the past"), std::string::npos);
  EXPECT_EQ(tracker.refused_count(), 3u);
  EXPECT_NE(tracker.last_refusal().find("plan 3"), std::string::npos);
  tracker.on_state(state_at({}), kT0);
  EXPECT_EQ(tracker.step(kT0).state, TrackerState::idle);
  // A start in the past within the lag is taken, sampled at the elapsed time.
  ASSERT_TRUE(tracker.on_trajectory(offer(traj, kT0 - 150'000, 4, kT0), kT0).accepted);
  const TrackerOutput& out = tracker.step(kT0);
  EXPECT_EQ(out.plan_id, 4);
  EXPECT_NEAR(out.t_s, 0.15, 1e-9);
}

TEST(Tracker, PendingTrajectoryStartsAtItsHandOffTime) {
  Rig rig;
  const Trajectory traj = test::straight(0.3, 1.0, +1);
  const std::int64_t start = rig.now + 250'000;
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(traj, start, 9, rig.now), rig.now).accepted);
  while (rig.now < start) {
    const TrackerOutput& out = rig.step();
    EXPECT_EQ(out.state, TrackerState::idle);
    EXPECT_TRUE(rig.tracker.has_pending());
  }
  const TrackerOutput& out = rig.step();
  EXPECT_EQ(out.state, TrackerState::tracking);
  EXPECT_EQ(out.plan_id, 9);
  EXPECT_NEAR(out.t_s, 0.0, 1e-9);
}

// Trajectory B continues A from A's state at the hand-off time t_h (as the planner re-plans).
Trajectory continuation(const Trajectory& a, double t_h, double turn_radius_m) {
  const TrajVector p = a.position(t_h), v = a.velocity(t_h), acc = a.acceleration(t_h);
  // Bend gently to the left over 3 s, then stop in 1 s.
  const double s = v.head<2>().norm();
  test::Knot k0{0.0, p, v, acc};
  test::Knot k1;
  k1.t_s = 3.0;
  const double phi = s * 3.0 / turn_radius_m;
  k1.p = p;
  k1.p[0] += turn_radius_m * std::sin(phi);
  k1.p[1] += turn_radius_m * (1.0 - std::cos(phi));
  k1.v = v;
  k1.v[0] = s * std::cos(phi);
  k1.v[1] = s * std::sin(phi);
  k1.a = TrajVector::Zero();
  test::Knot k2 = k1;
  k2.t_s = 4.0;
  k2.p.head<2>() += 0.5 * k1.v.head<2>();
  k2.v.setZero();
  return test::from_knots({k0, k1, k2}, +1, a.yaw_rad(t_h));
}

TEST(Tracker, HandOffWithoutJump) {
  Rig rig;
  const Trajectory a = test::straight(0.5, 4.0, +1);
  const double t_h = 2.5;
  const Trajectory b = continuation(a, t_h, 2.0);
  // Let the rig settle on A, offer B half a second before the hand-off.
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(a, rig.now, 1), rig.now).accepted);
  const std::int64_t hand_off = rig.now + static_cast<std::int64_t>(t_h * 1e6);
  double max_jump_v = 0.0, max_jump_w = 0.0, before_v = 0.0, before_w = 0.0;
  BaseCommand previous;
  bool offered = false, switched = false;
  while (rig.now < hand_off + 1'000'000) {
    if (!offered && rig.now >= hand_off - 500'000) {
      ASSERT_TRUE(rig.tracker.on_trajectory(offer(b, hand_off, 2, rig.now), rig.now).accepted);
      offered = true;
    }
    const std::int64_t t = rig.now;
    const TrackerOutput out = rig.step();
    ASSERT_EQ(out.state, TrackerState::tracking);
    EXPECT_EQ(out.plan_id, t >= hand_off ? 2 : 1);
    if (t >= hand_off - 1'000'000) {
      const double jv = std::abs(out.base.v_mps - previous.v_mps);
      const double jw = std::abs(out.base.omega_radps - previous.omega_radps);
      (t < hand_off ? before_v : max_jump_v) = std::max(t < hand_off ? before_v : max_jump_v, jv);
      (t < hand_off ? before_w : max_jump_w) = std::max(t < hand_off ? before_w : max_jump_w, jw);
      if (t == hand_off) switched = true;
    }
    previous = out.base;
  }
  EXPECT_TRUE(switched);
  // The reference's own change per period near the hand-off.
  double ref_dv = 0.0, ref_dw = 0.0;
  for (double t = 0.0; t < 1.0; t += 0.01) {
    const BaseMotion m0 = b.base_motion(t), m1 = b.base_motion(t + 0.01);
    ref_dv = std::max(ref_dv, std::abs(m1.signed_speed_mps - m0.signed_speed_mps));
    ref_dw = std::max(ref_dw, std::abs(m1.yaw_rate_radps - m0.yaw_rate_radps));
  }
  EXPECT_LE(max_jump_v, ref_dv + 2e-3);
  EXPECT_LE(max_jump_w, ref_dw + 2e-3);
  EXPECT_LT(max_jump_w, 0.02);  // a turn entered smoothly, not a step
}

TEST(Tracker, HandOffToDiscontinuousTrajectoryIsRateLimited) {
  // A trajectory that does not continue the current one (a step in the reference speed): the
  // command still changes by no more than the wheel acceleration limit allows.
  Rig rig;
  const Trajectory a = test::straight(0.2, 4.0, +1);
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(a, rig.now, 1), rig.now).accepted);
  rig.run_for(2.0);
  const Trajectory fast = test::arc(0.8, 1.0, 3.0, +1);
  // Start it where the robot is so no position fault trips.
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(fast, rig.now, 2), rig.now).accepted);
  rig.pose = {0.0, 0.0, 0.0};
  BaseCommand previous = rig.tracker.output().base;
  const BaseLimits limits = test::scout_limits();
  for (int i = 0; i < 30; ++i) {
    const TrackerOutput& out = rig.step();
    const double dv = std::abs(out.base.v_mps - previous.v_mps);
    EXPECT_LE(dv, limits.wheel_alpha_max_radps2 * 0.01 * limits.wheel_radius_m + 1e-9);
    previous = out.base;
  }
}

TEST(Tracker, EstopLatchesUntilRelease) {
  Rig rig;
  const Trajectory traj = test::straight(0.4, 6.0, +1);
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(traj, rig.now, 1), rig.now).accepted);
  rig.run_for(2.0);
  ASSERT_GT(rig.tracker.output().base.v_mps, 0.2);
  rig.tracker.on_estop(true, "operator: test", rig.now);
  const TrackerOutput& stopped = rig.step();  // the very next period
  EXPECT_EQ(stopped.state, TrackerState::estop);
  EXPECT_NE(stopped.message.find("operator: test"), std::string::npos);
  expect_zero(stopped);
  // Nothing un-latches it but a release: fresh state, a new trajectory, time.
  EXPECT_FALSE(rig.tracker.on_trajectory(offer(traj, rig.now, 2), rig.now).accepted);
  rig.tracker.on_estop(true, "operator: repeat", rig.now);
  rig.run_for(3.0);
  EXPECT_EQ(rig.step().state, TrackerState::estop);
  expect_zero(rig.tracker.output());
  rig.tracker.on_estop(false, "operator", rig.now);
  const TrackerOutput& released = rig.step();
  EXPECT_EQ(released.state, TrackerState::idle);
  EXPECT_NE(released.message.find("released"), std::string::npos);
  expect_zero(released);
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(test::straight(0.4, 1.0, +1), rig.now, 3), rig.now).accepted);
  rig.pose = {};
  EXPECT_EQ(rig.step().state, TrackerState::tracking);
}

TEST(Tracker, EstopReportedInStateStopsWithoutLatching) {
  Tracker tracker(params());
  ASSERT_TRUE(tracker.on_trajectory(offer(test::straight(0.3, 2.0, +1), kT0), kT0).accepted);
  MeasuredState s = state_at({});
  s.estop_active = true;
  tracker.on_state(s, kT0);
  EXPECT_EQ(tracker.step(kT0).state, TrackerState::estop);
  EXPECT_FALSE(tracker.estop_latched());
  s.estop_active = false;
  tracker.on_state(s, kT0 + kPeriod);
  EXPECT_EQ(tracker.step(kT0 + kPeriod).state, TrackerState::tracking);
}

TEST(Tracker, LargeTrackingErrorFaultsUntilNewTrajectory) {
  Rig rig;
  const Trajectory traj = test::straight(0.3, 4.0, +1);
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(traj, rig.now, 1), rig.now).accepted);
  rig.run_for(1.0);
  rig.pose.y_m += 0.8;  // pushed aside
  const TrackerOutput& out = rig.step();
  EXPECT_EQ(out.state, TrackerState::fault);
  expect_zero(out);
  rig.pose.y_m -= 0.8;
  rig.run_for(0.5);
  EXPECT_EQ(rig.step().state, TrackerState::fault);
  ASSERT_TRUE(rig.tracker.on_trajectory(offer(traj, rig.now, 2), rig.now).accepted);
  rig.pose = {};
  EXPECT_EQ(rig.step().state, TrackerState::tracking);
}

TEST(Tracker, ArmFeedForwardClampedToJointLimits) {
  TrackerParams p = params();
  p.joint_velocity_max_radps = JointVector::Constant(0.01);
  Tracker tracker(p);
  const Trajectory traj = test::straight(0.3, 1.0, +1);  // q1 moves at 0.5/3 rad/s mid-way
  ASSERT_TRUE(tracker.on_trajectory(offer(traj, kT0), kT0).accepted);
  tracker.on_state(state_at(BasePose{traj.position(1.5)[0], 0.0, 0.0}), kT0 + 1'500'000);
  const TrackerOutput& out = tracker.step(kT0 + 1'500'000);
  ASSERT_EQ(out.state, TrackerState::tracking);
  EXPECT_DOUBLE_EQ(out.qd_radps[0], 0.01);
  EXPECT_DOUBLE_EQ(out.q_rad[0], traj.position(1.5)[2]);
}

TEST(Tracker, InvalidParamsThrow) {
  TrackerParams p = params();
  p.gains.k_y_1pm2 = 0.0;
  EXPECT_THROW(Tracker{p}, std::invalid_argument);
  p = params();
  p.base_limits.wheel_radius_m = 0.0;
  EXPECT_THROW(Tracker{p}, std::invalid_argument);
}

}  // namespace
}  // namespace porter::tracker

namespace porter::tracker {
namespace {

TEST(Tracker, OverflowingTrajectoryNeverReachesTheTracker) {
  // Finite coefficients whose evaluation overflows (found by the fuzz target: the hold at the end
  // commanded infinite joint angles). Trajectory::create refuses them (|c| T^k is bounded), so no
  // trajectory the tracker can be given samples to a non-finite value.
  TrajectoryPiece piece;
  piece.duration_s = 1e3;
  piece.coeffs(5, 2) = 1e300;  // q1 = 1e300 t^5
  const TrajectoryResult r = Trajectory::create({piece}, 0.0);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("coeffs[5][2]"), std::string::npos) << r.error;
}

}  // namespace
}  // namespace porter::tracker
