#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <stdexcept>

#include "collision_test_utils.hpp"
#include "tbar_checker_suite.hpp"
#include "porter/core/kinematics.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"
#include "reference_collision.hpp"

namespace porter::planner {
namespace {

CollisionShape box_at(const Eigen::Vector3d& centre, const Eigen::Vector3d& size) {
  CollisionShape s;
  s.geometry = Box{size};
  s.T_parent_shape.translation() = centre;
  return s;
}

OccupancyGrid grid_with(const std::vector<CollisionShape>& obstacles, const Eigen::AlignedBox3d& bounds) {
  Scene scene;
  scene.bounds_W = bounds;
  scene.resolution_m = 0.05;
  scene.obstacles = obstacles;
  return voxelize(scene);
}

const Eigen::AlignedBox3d kRoom(Eigen::Vector3d(-3, -3, 0), Eigen::Vector3d(3, 3, 2.5));


class CheckerCases : public test::TBarCheckerSuite {};

TEST_F(CheckerCases, NoMapMeansCollision) {
  const KernelCollisionChecker fresh(*model_);
  EXPECT_TRUE(fresh.check(test::carrying(0, 0, 0)).in_collision);
  EXPECT_TRUE(fresh.check_base({0, 0, 0}).in_collision);
  EXPECT_EQ(fresh.name(), "kernels");
}

TEST_F(CheckerCases, MapEdgesGroundAndLimits) {
  checker_->set_map(grid_with({}, kRoom));
  EXPECT_FALSE(checker_->check(test::carrying(0, 0, 0.3)).in_collision);
  EXPECT_FALSE(checker_->check_base({0, 0, 0.3}).in_collision);
  // The base origin outside the map, or the base sticking out of it.
  EXPECT_EQ(checker_->check(test::carrying(3.2, 0, 0)).link, 0);
  EXPECT_EQ(checker_->check_base({-3.05, 0, 0}).link, 0);
  EXPECT_EQ(checker_->check_base({2.8, 0, 0}).link, 0);  // front 0.32 m beyond x = 3
  EXPECT_FALSE(checker_->check_base({2.5, 0, 0}).in_collision);
  EXPECT_EQ(checker_->check_base({0, 2.85, 0}).link, 0);
  // Far corner of the padding: every kernel point stays inside the padded array.
  EXPECT_TRUE(checker_->check(test::carrying(2.999, 2.999, 0.785)).in_collision);
  EXPECT_TRUE(checker_->check(test::carrying(-3.0, -3.0, -2.356)).in_collision);
  // NaN and joint limits.
  EXPECT_TRUE(checker_->check(test::carrying(std::nan(""), 0, 0)).in_collision);
  RobotConfiguration bad = test::carrying(0, 0, 0);
  bad.q_rad[2] = 0.5;  // joint 3 limits are [-2.967, 0]
  EXPECT_EQ(checker_->check(bad).link, 3);
  // The arm pointing down into the ground: links other than the base must stay above z = 0.
  RobotConfiguration down = test::carrying(0, 0, 0);
  down.q_rad << 0.0, 1.57, -0.2, 0.0, 1.2, 0.0;
  KinematicsWorkspace ws;
  forward_kinematics(*model_, down, ws);
  const test::ReferenceEnvironment reference(grid_with({}, kRoom), 0.0);
  ASSERT_GE(reference.first_colliding_link(*model_, down), 1) << "pose expected to reach the ground";
  const CollisionResult r = checker_->check(down);
  EXPECT_TRUE(r.in_collision);
  EXPECT_GE(r.link, 1);
  EXPECT_THROW(checker_->set_map(OccupancyGrid({0, 0, 0}, 0.1, {10, 10, 10})), std::invalid_argument);
}

TEST_F(CheckerCases, SafetyMarginAgainstTheReference) {
  // One small block; the base drives past it at offsets from touching to well clear.
  const OccupancyGrid grid = grid_with({box_at({0.0, 0.6, 0.3}, {0.1, 0.1, 0.6})}, kRoom);
  for (double margin : {0.0, 0.05, 0.1, 0.2}) {
    KernelCheckerSettings s;
    s.map.safety_margin_m = margin;
    KernelCollisionChecker checker(*model_, s);
    checker.set_map(grid);
    const test::ReferenceEnvironment reference(grid, margin);
    int hits = 0, misses = 0;
    for (double y = -0.1; y <= 0.35; y += 0.0071) {
      const BasePose b{0.013, y, 0.0};
      RobotConfiguration c = test::carrying(b.x_m, b.y_m, b.yaw_rad);
      KinematicsWorkspace ws;
      forward_kinematics(*model_, c, ws);
      const bool ref = reference.link_collides(*model_, ws, 0);
      const bool ker = checker.check_base(b).in_collision;
      if (ref) {
        EXPECT_TRUE(ker) << "margin " << margin << " y " << y;
      }
      if (ker && !ref) {
        EXPECT_TRUE(reference.link_within(*model_, ws, 0, checker.kernels().inflation_bound_m(0) + 0.044)) << y;
      }
      hits += ker;
      misses += !ker;
    }
    EXPECT_GT(hits, 0) << margin;
    EXPECT_GT(misses, 0) << margin;
  }
}

TEST_F(CheckerCases, MapUpdatesMatchAFreshChecker) {
  OccupancyGrid grid = grid_with({box_at({1.5, 0.0, 1.0}, {0.2, 2.0, 2.0})}, kRoom);
  checker_->set_map(grid);
  const RobotConfiguration c = test::carrying(0.0, 0.0, 0.0);
  EXPECT_FALSE(checker_->check(c).in_collision);
  // A pillar appears next to the robot: the next map (same lattice) is an incremental update.
  const OccupancyGrid pillar =
      grid_with({box_at({1.5, 0.0, 1.0}, {0.2, 2.0, 2.0}), box_at({0.0, 0.35, 1.0}, {0.2, 0.2, 2.0})}, kRoom);
  checker_->set_map(pillar);
  EXPECT_TRUE(checker_->last_map_update().incremental);
  EXPECT_GT(checker_->last_map_update().changed_voxels, 0);
  EXPECT_TRUE(checker_->check(c).in_collision);
  KernelCollisionChecker fresh(*model_);
  fresh.set_map(pillar);
  std::mt19937_64 rng(41);
  Scene room;
  room.bounds_W = kRoom;
  for (int i = 0; i < 3000; ++i) {
    const RobotConfiguration r = test::random_configuration(*model_, room, rng, 0.5);
    ASSERT_EQ(checker_->check(r).in_collision, fresh.check(r).in_collision);
  }
  // And it goes away again.
  checker_->set_map(grid);
  EXPECT_FALSE(checker_->check(c).in_collision);
}

TEST_F(CheckerCases, BaseCheckAgreesWithTheWholeBodyCheck) {
  const Scene scene = test::shipped_scene("forest");
  checker_->set_map(voxelize(scene));
  std::mt19937_64 rng(42);
  int base_hits = 0;
  for (int i = 0; i < 5000; ++i) {
    const RobotConfiguration c = test::random_configuration(*model_, scene, rng);
    const bool base = checker_->check_base(c.base).in_collision;
    base_hits += base;
    if (base) {
      EXPECT_EQ(checker_->check_environment(c).link, 0);
    } else {
      EXPECT_NE(checker_->check_environment(c).link, 0);
    }
  }
  EXPECT_GT(base_hits, 100);
}

TEST(CheckerScenes, ShippedStartAndGoalAreFreeWithTheirPayload) {
  for (const std::string name : {"tunnel", "forest", "bridge", "empty"}) {
    const Scene scene = test::shipped_scene(name);
    const RobotModel model = attach_payload(test::shipped_robot(), load_payload(scene.payload_file));
    KernelCollisionChecker checker(model);
    const OccupancyGrid grid = voxelize(scene);
    checker.set_map(grid);
    const test::ReferenceEnvironment reference(grid, 0.0);
    for (const RobotConfiguration& c : {scene.start, scene.goal}) {
      EXPECT_EQ(reference.first_colliding_link(model, c), -1) << name;
      // The kernel check may only reject it when something is within its inflation bound.
      KinematicsWorkspace ws;
      forward_kinematics(model, c, ws);
      bool near_something = false;
      for (int k = 0; k < kNumLinks; ++k)
        near_something =
            near_something || reference.link_within(model, ws, k, checker.kernels().inflation_bound_m(k) + 0.044);
      if (!near_something) {
        EXPECT_FALSE(checker.check(c).in_collision) << name << " link " << checker.check(c).link;
      } else if (checker.check(c).in_collision) {
        std::cout << "note: " << name
                  << " start/goal lies within the kernel inflation of the map's bounds or an obstacle\n";
      }
    }
  }
}

TEST_F(CheckerCases, StorageIsReported) {
  checker_->set_map(grid_with({}, kRoom));
  const KernelStorage st = checker_->storage();
  EXPECT_EQ(st.kernel_count, checker_->kernels().kernel_count());
  EXPECT_GT(st.robot_kernel_bytes, 0u);
  EXPECT_GT(st.self_collision_bytes, 0u);
  EXPECT_GT(st.map_kernel_bytes, 0u);
  EXPECT_LT(st.kernel_count, 2000);  // sum of the per-joint counts, not their product
}

}  // namespace
}  // namespace porter::planner
