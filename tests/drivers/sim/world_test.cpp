// The simulated world: obstacles added and removed at run time (with a version for sensors that
// cache them) and the ground-truth history sensors query at any time of a step.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "porter/sim/world.hpp"

namespace porter::sim {
namespace {

Scene test_scene() {
  Scene scene;
  scene.name = "test";
  scene.bounds_W = Eigen::AlignedBox3d(Eigen::Vector3d(-5, -5, 0), Eigen::Vector3d(5, 5, 2));
  CollisionShape wall;
  wall.geometry = Box{Eigen::Vector3d(0.2, 4.0, 1.0)};
  wall.T_parent_shape.translation() = Eigen::Vector3d(3, 0, 0.5);
  wall.name = "wall";
  scene.obstacles.push_back(wall);
  scene.start.base = {1.0, 2.0, 0.5};
  return scene;
}

RobotSample sample(double t, double x, double yaw, double q0 = 0.0) {
  RobotSample s;
  s.t_s = t;
  s.config.base = {x, -x, yaw};
  s.config.q_rad[0] = q0;
  s.v_mps = x;
  return s;
}

TEST(SimWorld, BoxesAppearAndObstaclesDisappearWithAVersion) {
  World world(test_scene(), RobotModel{});
  ASSERT_EQ(world.obstacles().size(), 1u);
  const std::uint64_t v0 = world.obstacles_version();
  ASSERT_EQ(world.add_box("crate", Eigen::Vector3d(1, 1, 0.25), Eigen::Vector3d(0.4, 0.2, 0.5),
                          M_PI / 2),
            ObstacleStatus::ok);
  EXPECT_GT(world.obstacles_version(), v0);
  ASSERT_EQ(world.obstacles().size(), 2u);
  const CollisionShape& crate = world.obstacles()[1];
  EXPECT_EQ(crate.name, "crate");
  // Rotated a quarter turn: 0.2 m wide along x, 0.4 m along y.
  EXPECT_TRUE(shape_contains(crate, Eigen::Vector3d(1.0, 1.18, 0.25)));
  EXPECT_FALSE(shape_contains(crate, Eigen::Vector3d(1.18, 1.0, 0.25)));
  const std::uint64_t v1 = world.obstacles_version();
  EXPECT_EQ(world.add_box("crate", Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 0),
            ObstacleStatus::duplicate_name);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(world.add_box("b", Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 1), 0),
            ObstacleStatus::invalid);
  EXPECT_EQ(world.add_box("b", Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(-1, 1, 1), 0),
            ObstacleStatus::invalid);
  EXPECT_EQ(world.add_box("b", Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d(1, 1, 1), 0),
            ObstacleStatus::invalid);
  EXPECT_EQ(world.add_box("", Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 0),
            ObstacleStatus::invalid);
  EXPECT_EQ(world.obstacles_version(), v1) << "refused changes do not bump the version";
  EXPECT_EQ(world.remove_obstacle("wall"), ObstacleStatus::ok);  // a scene obstacle
  EXPECT_EQ(world.remove_obstacle("wall"), ObstacleStatus::not_found);
  ASSERT_EQ(world.obstacles().size(), 1u);
  EXPECT_EQ(world.obstacles()[0].name, "crate");
  EXPECT_GT(world.obstacles_version(), v1);
  EXPECT_EQ(world.scene().obstacles.size(), 1u) << "the scene itself is unchanged";
}

TEST(SimWorld, RobotAtInterpolatesBetweenStepsAndClampsOutside) {
  World world(test_scene(), RobotModel{});
  EXPECT_FALSE(world.has_truth());
  EXPECT_DOUBLE_EQ(world.robot_at(3.0).config.base.x_m, 1.0) << "before any record: the start";
  world.record(sample(1.0, 0.0, 3.0, 0.0));
  world.record(sample(1.002, 0.2, -3.0, 1.0));  // yaw crosses +-pi
  const RobotSample mid = world.robot_at(1.001);
  EXPECT_NEAR(mid.config.base.x_m, 0.1, 1e-12);
  EXPECT_NEAR(mid.config.base.y_m, -0.1, 1e-12);
  EXPECT_NEAR(mid.config.q_rad[0], 0.5, 1e-12);
  EXPECT_NEAR(mid.v_mps, 0.1, 1e-12);
  // The shorter arc from 3.0 to -3.0 passes through pi.
  EXPECT_NEAR(std::abs(mid.config.base.yaw_rad), M_PI, 1e-9);
  EXPECT_DOUBLE_EQ(world.robot_at(0.5).config.base.x_m, 0.0);
  EXPECT_DOUBLE_EQ(world.robot_at(2.0).config.base.x_m, 0.2);
  EXPECT_DOUBLE_EQ(world.latest().t_s, 1.002);
}

TEST(SimWorld, HistoryKeepsTheConfiguredSpan) {
  World world(test_scene(), RobotModel{}, 0.5);
  for (int k = 0; k <= 2000; ++k) world.record(sample(k * 1e-3, k * 1e-3, 0.0));
  EXPECT_LE(world.history_start_s(), 2.0 - 0.5);
  EXPECT_GT(world.history_start_s(), 2.0 - 0.51);
  EXPECT_NEAR(world.robot_at(1.6).config.base.x_m, 1.6, 1e-12);
  world.set_utime_origin(1000000);
  EXPECT_EQ(world.utime_at(1.5), 2500000);
}

}  // namespace
}  // namespace porter::sim
