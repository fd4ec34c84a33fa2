// ExactClearanceAcceptance: a trajectory is accepted exactly when its exact clearance reaches the
// margin. The robot stands still at the bridge scene's start pose next to one wall; moving the wall
// away by d must raise the measured clearance by d (a property of the geometry, not of the code
// that measures it), and the verdict must switch at the margin.

#include <gtest/gtest.h>

#include <stdexcept>

#include "pipeline_fixtures.hpp"
#include "porter/pipeline/exact_acceptance.hpp"
#include "porter/planner/collision/kernel_robot.hpp"

namespace porter::pipeline {
namespace {

/// The robot held at `c` for one second (one piece, all higher coefficients zero).
Trajectory standing_at(const RobotConfiguration& c) {
  TrajectoryPiece p;
  p.duration_s = 1.0;
  p.coeffs.row(0) << c.base.x_m, c.base.y_m, c.q_rad.transpose();
  TrajectoryResult r = Trajectory::create({p}, c.base.yaw_rad);
  EXPECT_TRUE(r.trajectory.has_value()) << r.error;
  return *r.trajectory;
}

struct Fixture {
  Scene bridge = testing::scene("bridge");
  RobotModel bare = load_robot_model(testing::source_dir() + "/config/robots/scout_mini_piper/robot.yaml");
  Payload payload = load_payload(bridge.payload_file);

  /// The scene with its obstacles replaced by one wall in front of the start pose (+x of the base),
  /// its near face `gap_m` ahead of the base origin.
  Scene with_wall(double gap_m) const {
    Scene s = bridge;
    CollisionShape wall;
    wall.name = "wall";
    wall.geometry = Box{Eigen::Vector3d(0.2, 4.0, 2.0)};
    const Eigen::Isometry3d T_W_B = bridge.start.base.T_W_B();
    wall.T_parent_shape = T_W_B * Eigen::Translation3d(gap_m + 0.1, 0.0, 1.0);
    s.obstacles = {wall};
    return s;
  }

  ExactClearance clearance(double gap_m, double margin_m, planner::AcceptanceResult* r) const {
    ExactAcceptanceSettings settings;
    settings.margin_m = margin_m;
    const ExactClearanceAcceptance acceptance(bare, payload, with_wall(gap_m), settings);
    ExactClearance c;
    *r = acceptance.check(standing_at(bridge.start), &c);
    return c;
  }
};

TEST(ExactAcceptance, ClearanceFollowsTheObstacleAndTheVerdictSwitchesAtTheMargin) {
  const Fixture f;
  planner::AcceptanceResult r;
  // With the wall far away the payload's height over the ground is the clearance; the wall cases
  // below stay under it.
  const ExactClearance ground = f.clearance(10.0, 0.0, &r);
  ASSERT_EQ(ground.obstacle, "ground");
  const ExactClearance near = f.clearance(1.0, 0.0, &r);
  ASSERT_TRUE(r.accepted);
  ASSERT_EQ(near.obstacle, "wall");
  ASSERT_GT(near.min_m, 0.0);
  const double d = 0.5 * (ground.min_m - near.min_m);
  ASSERT_GT(d, 0.005);
  // The nearest body faces the wall's flat side: moving the wall d farther adds d.
  const ExactClearance far = f.clearance(1.0 + d, 0.0, &r);
  EXPECT_EQ(far.obstacle, "wall");
  EXPECT_NEAR(far.min_m - near.min_m, d, 1e-4);
  // The margin decides.
  f.clearance(1.0, near.min_m - 1e-3, &r);
  EXPECT_TRUE(r.accepted);
  f.clearance(1.0, near.min_m + 1e-3, &r);
  EXPECT_FALSE(r.accepted);
  EXPECT_GE(r.link, 0);
  EXPECT_EQ(r.other_link, -1);
}

TEST(ExactAcceptance, AWallThroughTheRobotIsACollision) {
  const Fixture f;
  planner::AcceptanceResult r;
  const ExactClearance c = f.clearance(-0.1, 0.0, &r);
  EXPECT_FALSE(r.accepted);
  EXPECT_LT(c.min_m, 0.0);
  EXPECT_GE(r.link, 0);
}

// The kernel filter only decides where exact checks are needed: with it, the verdicts are those of
// the exact check over the whole trajectory, on a trajectory that drives the robot towards the wall.
TEST(ExactAcceptance, TheKernelFilterKeepsTheExactVerdict) {
  const Fixture f;
  const RobotModel with_payload = attach_payload(f.bare, f.payload);
  PlannerSettings settings = testing::shipped_settings(f.bridge);
  const auto kernel_robot = std::make_shared<const planner::KernelRobot>(with_payload, settings.kernels);
  // 1.5 m forward in 3 s (a quintic from rest to rest along the base's x axis).
  const RobotConfiguration& s0 = f.bridge.start;
  const Eigen::Vector2d dir(std::cos(s0.base.yaw_rad), std::sin(s0.base.yaw_rad));
  TrajectoryPiece p;
  p.duration_s = 3.0;
  p.coeffs.row(0) << s0.base.x_m, s0.base.y_m, s0.q_rad.transpose();
  const double L = 1.5, T = 3.0;  // x(t) = L (10 u^3 - 15 u^4 + 6 u^5), u = t / T
  const double a3 = 10.0 * L / (T * T * T), a4 = -15.0 * L / (T * T * T * T), a5 = 6.0 * L / (T * T * T * T * T);
  p.coeffs.block<1, 2>(3, 0) = a3 * dir.transpose();
  p.coeffs.block<1, 2>(4, 0) = a4 * dir.transpose();
  p.coeffs.block<1, 2>(5, 0) = a5 * dir.transpose();
  TrajectoryResult tr = Trajectory::create({p}, s0.base.yaw_rad);
  ASSERT_TRUE(tr.trajectory.has_value()) << tr.error;
  int accepted = 0, rejected = 0;
  for (double gap : {1.6, 2.505, 2.515, 2.6, 3.5}) {
    const Scene scene = f.with_wall(gap);
    ExactAcceptanceSettings es;
    es.margin_m = 0.02;
    const ExactClearanceAcceptance slow(f.bare, f.payload, scene, es);
    const ExactClearanceAcceptance fast(f.bare, f.payload, scene, es, kernel_robot, voxelize(scene));
    ExactClearance cs, cf;
    const planner::AcceptanceResult rs = slow.check(*tr.trajectory, &cs);
    const planner::AcceptanceResult rf = fast.check(*tr.trajectory, &cf);
    EXPECT_EQ(rs.accepted, rf.accepted) << "gap " << gap << ": exact " << cs.min_m << " m";
    EXPECT_GT(cf.filter_samples, 10);
    (rs.accepted ? accepted : rejected)++;
    if (gap >= 3.5) {
      EXPECT_EQ(cf.windows, 0) << "far from the wall the filter clears everything";
    }
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

TEST(ExactAcceptance, StatesItsMarginAndRefusesABadOne) {
  const Fixture f;
  ExactAcceptanceSettings s;
  s.margin_m = 0.035;
  const ExactClearanceAcceptance a(f.bare, f.payload, f.bridge, s);
  EXPECT_DOUBLE_EQ(a.clearance_margin_m(), 0.035);
  EXPECT_EQ(a.name(), "exact");
  s.margin_m = -0.01;
  EXPECT_THROW(ExactClearanceAcceptance(f.bare, f.payload, f.bridge, s), std::invalid_argument);
}

}  // namespace
}  // namespace porter::pipeline
