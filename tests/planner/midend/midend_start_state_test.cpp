// A trajectory that starts from a moving state (a hand-off onto a new plan while driving): the
// first piece continues the given velocity and acceleration, the result meets the limits, and a
// start state the mid-end cannot use is refused.
#include <cmath>

#include <gtest/gtest.h>

#include "porter/midend/midend.hpp"
#include "synthetic_paths.hpp"
#include "trajectory_checks.hpp"

namespace porter::midend {
namespace {

StartDerivatives moving_start(const planner::WholeBodyPath& path, double speed_mps, double accel_mps2) {
  const double yaw = path.segments.front().nodes.front().config.base.yaw_rad;
  StartDerivatives s;
  s.velocity << speed_mps * std::cos(yaw), speed_mps * std::sin(yaw), 0.05, -0.05, 0.0, 0.05, 0.0, 0.0;
  s.acceleration << accel_mps2 * std::cos(yaw), accel_mps2 * std::sin(yaw), 0.0, 0.02, 0.0, 0.0, 0.0, 0.0;
  return s;
}

TEST(MidendStartState, TheFirstPieceContinuesTheGivenVelocityAndAcceleration) {
  const planner::WholeBodyPath path = testing::forward_with_turn();
  const MidEnd midend(testing::scout_mini_piper_model());
  for (const double speed : {0.2, 0.5}) {
    const StartDerivatives start = moving_start(path, speed, 0.1);
    const MidendResult r = midend.solve(path, planner::Deadline(5.0), start);
    ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
    const Trajectory& t = *r.trajectory;
    EXPECT_LT((t.velocity(0.0) - start.velocity).norm(), 1e-9) << speed;
    EXPECT_LT((t.acceleration(0.0) - start.acceleration).norm(), 1e-9) << speed;
    const TrajVector p0 = t.position(0.0);
    const RobotConfiguration& first = path.segments.front().nodes.front().config;
    EXPECT_NEAR(p0[0], first.base.x_m, 1e-9);
    EXPECT_NEAR(p0[1], first.base.y_m, 1e-9);
    // Moving along the heading, forward: the yaw at the start is the node's.
    EXPECT_NEAR(t.yaw_rad(0.0), first.base.yaw_rad, 1e-9);
    // It still ends at rest at the goal and meets every limit (the mid-end's own result check
    // passed: kConstraintViolation otherwise); the solution carries the start state.
    EXPECT_LT(t.velocity(t.total_duration_s()).norm(), 1e-9);
    ASSERT_TRUE(r.solution.has_value());
    EXPECT_EQ(r.solution->reference.start.velocity, start.velocity);
    const testing::CheckReport c = testing::check_trajectory(t, path, midend.limits(), midend.settings());
    EXPECT_TRUE(c.finite);
    EXPECT_LT(c.continuity_error, 1e-7);
    EXPECT_EQ(c.reversals, 0);
  }
}

TEST(MidendStartState, AStartStateTheMidendCannotUseIsRefused) {
  const MidEnd midend(testing::scout_mini_piper_model());
  StartDerivatives bad;
  bad.velocity[0] = std::nan("");
  EXPECT_EQ(midend.solve(testing::forward_with_turn(), planner::Deadline(1.0), bad).status, planner::Status::kInvalidStart);
  // A path without motion cannot continue a moving start.
  testing::PathBuilder still({0.0, 0.0, 0.0}, testing::carry_pose());
  planner::WholeBodyPath p = still.build();
  const StartDerivatives moving = moving_start(testing::forward_with_turn(), 0.3, 0.0);
  const MidendResult r = midend.solve(p, planner::Deadline(1.0), moving);
  EXPECT_EQ(r.status, planner::Status::kInvalidStart) << r.message;
  EXPECT_FALSE(r.trajectory.has_value());
}

}  // namespace
}  // namespace porter::midend
