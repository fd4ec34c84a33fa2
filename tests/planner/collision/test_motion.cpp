#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "collision_test_utils.hpp"
#include "tbar_checker_suite.hpp"
#include "porter/core/kinematics.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::planner {
namespace {

CollisionShape column(double x, double y, double radius) {
  CollisionShape s;
  s.geometry = Cylinder{radius, 2.5};
  s.T_parent_shape.translation() = Eigen::Vector3d(x, y, 1.25);
  return s;
}

OccupancyGrid room_with(const std::vector<CollisionShape>& obstacles) {
  Scene scene;
  scene.bounds_W = Eigen::AlignedBox3d(Eigen::Vector3d(-3, -3, 0), Eigen::Vector3d(5, 3, 2.5));
  scene.resolution_m = 0.05;
  scene.obstacles = obstacles;
  return voxelize(scene);
}


class MotionTest : public test::TBarCheckerSuite {};

TEST_F(MotionTest, ThinColumnCrossedByTheBaseIsCaught) {
  checker_->set_map(room_with({column(1.0, 0.0, 0.015)}));  // 3 cm: one or two voxels wide
  const RobotConfiguration from = test::carrying(-0.5, 0.0, 0.0), to = test::carrying(2.5, 0.0, 0.0);
  ASSERT_FALSE(checker_->check(from).in_collision);
  ASSERT_FALSE(checker_->check(to).in_collision);
  EXPECT_TRUE(checker_->check_motion(from, to).in_collision);
  EXPECT_TRUE(checker_->check_motion(to, from).in_collision);
  // Beside the column: free.
  EXPECT_FALSE(checker_->check_motion(test::carrying(-0.5, -1.8, 0.0), test::carrying(2.5, -1.8, 0.0)).in_collision);
}

TEST_F(MotionTest, ThinColumnSweptByThePayloadIsCaught) {
  // The base stays put; joint 1 swings the T bar through a column beside the robot.
  const RobotConfiguration a = test::carrying(0.0, 0.0, 0.0, -1.2), b = test::carrying(0.0, 0.0, 0.0, 1.2);
  KinematicsWorkspace ws;
  forward_kinematics(*model_, test::carrying(0.0, 0.0, 0.0, 0.0), ws);
  const Eigen::Vector3d tip = ws.T_W_L[kEndEffectorLink] * Eigen::Vector3d(0.0, 0.0, 0.3);  // along the stem
  checker_->set_map(room_with({column(tip.x(), tip.y(), 0.015)}));
  ASSERT_FALSE(checker_->check(a).in_collision);
  ASSERT_FALSE(checker_->check(b).in_collision);
  ASSERT_TRUE(checker_->check(test::carrying(0.0, 0.0, 0.0, 0.0)).in_collision);
  EXPECT_TRUE(checker_->check_motion(a, b).in_collision);
}

TEST_F(MotionTest, SamplesRespectTheStepBound) {
  checker_->set_map(room_with({}));
  const RobotConfiguration a = test::carrying(-1.0, 0.3, 3.0, -1.0), b = test::carrying(0.5, -0.4, -2.9, 0.8);
  const int n = checker_->motion_intervals(a, b);
  ASSERT_GT(n, 10);
  // Measure the largest displacement of the links' shape vertices between neighbouring samples.
  const double dyaw = std::remainder(b.base.yaw_rad - a.base.yaw_rad, 2 * M_PI);
  double worst = 0.0;
  KinematicsWorkspace prev, cur;
  for (int i = 0; i <= n; ++i) {
    RobotConfiguration c;
    const double s = static_cast<double>(i) / n;
    c.base = {a.base.x_m + s * (b.base.x_m - a.base.x_m), a.base.y_m + s * (b.base.y_m - a.base.y_m),
              a.base.yaw_rad + s * dyaw};
    c.q_rad = a.q_rad + s * (b.q_rad - a.q_rad);
    forward_kinematics(*model_, c, cur);
    if (i > 0)
      for (int k = 0; k < kNumLinks; ++k)
        for (const auto& shape : model_->links[static_cast<std::size_t>(k)].shapes)
          for (const auto& v : shape_to_mesh(shape, 8).vertices_m)
            worst = std::max(
                worst,
                (cur.T_W_L[static_cast<std::size_t>(k)] * v - prev.T_W_L[static_cast<std::size_t>(k)] * v).norm());
    prev = cur;
  }
  EXPECT_LE(worst, checker_->motion_step_m() + 1e-9);
  EXPECT_GT(worst, 0.2 * checker_->motion_step_m());  // and the bound is not absurdly loose
  EXPECT_FALSE(checker_->check_motion(a, b).in_collision);
  EXPECT_EQ(checker_->motion_intervals(a, a), 1);
}

TEST_F(MotionTest, TrajectoryThroughAThinColumnIsCaught) {
  checker_->set_map(room_with({column(1.0, 0.0, 0.015)}));
  auto straight = [](double y) {
    TrajVector p0 = TrajVector::Zero(), p1 = TrajVector::Zero(), zero = TrajVector::Zero();
    p0 << -0.5, y, 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
    p1 << 2.5, y, 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
    TrajVector v = TrajVector::Zero();
    v[0] = 0.5;  // cruising along +x at both ends
    TrajectoryPiece piece;
    piece.duration_s = 6.0;
    piece.coeffs = quintic_hermite(p0, v, zero, p1, v, zero, 6.0);
    return Trajectory::create({piece}, 0.0);
  };
  const TrajectoryResult through = straight(0.0), beside = straight(-1.8);
  ASSERT_TRUE(through.ok());
  ASSERT_TRUE(beside.ok());
  EXPECT_TRUE(checker_->check_trajectory(*through.trajectory).in_collision);
  EXPECT_FALSE(checker_->check_trajectory(*beside.trajectory).in_collision);
}

TEST_F(MotionTest, SelfCollisionAlongATrajectoryIsFoundBehindAnEnvironmentHit) {
  // The base stands in a column (an environment hit at t = 0, which check_trajectory reports
  // first) while the arm swings the T bar down through the base and back.
  checker_->set_map(room_with({column(0.0, 0.0, 0.1)}));
  JointVector carry, down;
  carry << 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
  down << 3.0, 2.8, -0.3, 0.0, 0.0, 0.0;  // self-colliding (test_self_collision.cpp)
  ASSERT_TRUE(checker_->check_self(down).in_collision);
  ASSERT_FALSE(checker_->check_self(carry).in_collision);
  auto arm_motion = [](const JointVector& a, const JointVector& b) {
    TrajVector p0 = TrajVector::Zero(), p1 = TrajVector::Zero(), zero = TrajVector::Zero();
    p0.tail<kNumArmJoints>() = a;
    p1.tail<kNumArmJoints>() = b;
    std::vector<TrajectoryPiece> pieces(2);
    pieces[0].duration_s = pieces[1].duration_s = 4.0;
    pieces[0].coeffs = quintic_hermite(p0, zero, zero, p1, zero, zero, 4.0);
    pieces[1].coeffs = quintic_hermite(p1, zero, zero, p0, zero, zero, 4.0);
    return Trajectory::create(pieces, 0.0);
  };
  const TrajectoryResult swing = arm_motion(carry, down), still = arm_motion(carry, carry);
  ASSERT_TRUE(swing.ok());
  ASSERT_TRUE(still.ok());
  const CollisionResult first = checker_->check_trajectory(*swing.trajectory);
  EXPECT_TRUE(first.in_collision);
  EXPECT_EQ(first.other_link, -1) << "the environment hit comes first";
  const CollisionResult self = checker_->check_trajectory_self(*swing.trajectory);
  EXPECT_TRUE(self.in_collision);
  EXPECT_GE(self.other_link, 0);
  EXPECT_TRUE(checker_->check_trajectory(*still.trajectory).in_collision);
  EXPECT_FALSE(checker_->check_trajectory_self(*still.trajectory).in_collision);
}

}  // namespace
}  // namespace porter::planner
