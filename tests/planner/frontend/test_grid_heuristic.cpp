// Grid heuristic: the inscribed disc of the base, soundness of blocked cells against the exact
// base check, distances in the open, unreachable goals.

#include <random>

#include <gtest/gtest.h>

#include "exact_checker.hpp"
#include "frontend_test_utils.hpp"
#include "porter/frontend/grid_heuristic.hpp"
#include "test_scenes.hpp"

namespace porter::frontend {
namespace {

TEST(GridHeuristic, InscribedDiscOfTheScoutMini) {
  const Scene scene = test::scene_from_text(test::open_scene_yaml());
  const RobotModel model = test::model_for(scene);
  const InscribedDisc disc = base_inscribed_disc(model);
  // The chassis box is 0.42 m wide: the disc is at most 0.21 m and at least 0.2 m (5 mm steps).
  EXPECT_GE(disc.radius_m, 0.2);
  EXPECT_LE(disc.radius_m, 0.21);
  EXPECT_GT(disc.z_m, 0.09);
}

TEST(GridHeuristic, BlockedCellsCollideForEveryPoseInside) {
  const Scene scene = test::scene_from_text(test::gap_scene_yaml());
  const RobotModel model = test::model_for(scene);
  const OccupancyGrid grid = voxelize(scene);
  test::ExactCollisionChecker exact(model);
  exact.set_map(grid);
  GridHeuristic h;
  h.build(grid, base_inscribed_disc(model), 0.1);
  ASSERT_GT(h.blocked_count(), 0);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ux(-2.0, 7.0), uy(-3.5, 3.5), ua(-M_PI, M_PI);
  int blocked_samples = 0;
  for (int k = 0; k < 20000 && blocked_samples < 400; ++k) {
    const BasePose p{ux(rng), uy(rng), ua(rng)};
    if (!h.blocked(p.x_m, p.y_m)) continue;
    ++blocked_samples;
    EXPECT_TRUE(exact.check_base(p).in_collision) << p.x_m << " " << p.y_m << " " << p.yaw_rad;
  }
  EXPECT_GE(blocked_samples, 100);
}

TEST(GridHeuristic, OpenFloorDistanceIsCloseToEuclidean) {
  const Scene scene = test::scene_from_text(test::open_scene_yaml());
  const RobotModel model = test::model_for(scene);
  const OccupancyGrid grid = voxelize(scene);
  GridHeuristic h;
  h.build(grid, base_inscribed_disc(model), 0.1);
  ASSERT_TRUE(h.set_goal(5.0, 0.0));
  EXPECT_NEAR(h.distance(5.0, 0.0), 0.0, 1e-9);
  for (const auto& p : {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(1.0, 2.0), Eigen::Vector2d(4.0, -2.5)}) {
    const double e = (p - Eigen::Vector2d(5.0, 0.0)).norm();
    const double d = h.distance(p.x(), p.y());
    EXPECT_LE(d, 1.09 * e);          // octile distance over-estimates by < 8.3 %
    EXPECT_GE(d, e - 0.3);           // minus the cell diagonal and the cell offsets
  }
  EXPECT_TRUE(std::isinf(h.distance(100.0, 0.0)));
}

TEST(GridHeuristic, DetourAroundTheWallAndEnclosedGoal) {
  {
    const Scene scene = test::scene_from_text(test::gap_scene_yaml());
    const RobotModel model = test::model_for(scene);
    GridHeuristic h;
    h.build(voxelize(scene), base_inscribed_disc(model), 0.1);
    ASSERT_TRUE(h.set_goal(5.0, 0.0));
    // Through the gap (y >= 1.1 + the base radius): at least 2 * hypot(2.5, 1.3) - slack.
    EXPECT_GT(h.distance(0.0, 0.0), 2.0 * std::hypot(2.5, 1.3) - 0.3);
    EXPECT_TRUE(std::isfinite(h.distance(0.0, 0.0)));
  }
  {
    const Scene scene = test::scene_from_text(test::walled_goal_scene_yaml());
    const RobotModel model = test::model_for(scene);
    GridHeuristic h;
    h.build(voxelize(scene), base_inscribed_disc(model), 0.1);
    ASSERT_TRUE(h.set_goal(5.0, 0.0));
    EXPECT_TRUE(std::isinf(h.distance(0.0, 0.0)));
    EXPECT_TRUE(std::isfinite(h.distance(5.5, 0.5)));
  }
}

}  // namespace
}  // namespace porter::frontend
