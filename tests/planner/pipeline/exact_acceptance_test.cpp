// ExactClearanceAcceptance: a trajectory is accepted exactly when its exact clearance reaches the
// margin. The robot stands still at the bridge scene's start pose next to one wall; moving the wall
// away by d must raise the measured clearance by d (a property of the geometry, not of the code
// that measures it), and the verdict must switch at the margin.

#include <gtest/gtest.h>

#include <stdexcept>

#include "pipeline_fixtures.hpp"
#include "porter/pipeline/exact_acceptance.hpp"

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
  const ExactClearance near = f.clearance(1.0, 0.0, &r);
  ASSERT_TRUE(r.accepted);
  ASSERT_EQ(near.obstacle, "wall");
  ASSERT_GT(near.min_m, 0.05);
  ASSERT_LT(near.min_m, 1.0);
  // The nearest body faces the wall's flat side: moving the wall 7 cm away adds 7 cm.
  const ExactClearance far = f.clearance(1.07, 0.0, &r);
  EXPECT_NEAR(far.min_m - near.min_m, 0.07, 1e-4);
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
