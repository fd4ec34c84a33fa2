// Hybrid A*: exact goal, base collision-free along arcs and chords, turning radius and yaw tied
// to the direction, detours, gear switches, no_path, invalid endpoints, determinism.

#include <gtest/gtest.h>

#include "exact_checker.hpp"
#include "porter/planner/angle.hpp"
#include "frontend_test_utils.hpp"
#include "porter/frontend/hybrid_astar.hpp"
#include "test_scenes.hpp"

namespace porter::frontend {
namespace {

struct Fixture {
  explicit Fixture(const std::string& yaml)
      : scene(test::scene_from_text(yaml)), model(test::model_for(scene)), grid(voxelize(scene)), exact(model) {
    exact.set_map(grid);
  }
  Scene scene;
  RobotModel model;
  OccupancyGrid grid;
  test::ExactCollisionChecker exact;
};

/// Base-path promises: exact ends, spacing, free samples and chords, turning radius, yaw tied
/// to the driving direction.
void expect_valid_base_path(const HybridAStarResult& r, const Fixture& f, double radius, double step) {
  ASSERT_EQ(r.report.status, planner::Status::kSuccess) << r.report.message;
  ASSERT_GE(r.path.size(), 2u);
  auto same_pose = [](const BasePose& a, const BasePose& b) {
    return std::abs(a.x_m - b.x_m) < 1e-9 && std::abs(a.y_m - b.y_m) < 1e-9 && std::abs(planner::wrap_angle_rad(a.yaw_rad - b.yaw_rad)) < 1e-9;
  };
  EXPECT_TRUE(same_pose(r.path.front().pose, f.scene.start.base));
  EXPECT_TRUE(same_pose(r.path.back().pose, f.scene.goal.base));
  for (std::size_t i = 0; i < r.path.size(); ++i) {
    EXPECT_FALSE(f.exact.check_base(r.path[i].pose).in_collision) << i;
    EXPECT_TRUE(r.path[i].eta == 1 || r.path[i].eta == -1);
    if (i == 0) continue;
    const BasePose& a = r.path[i - 1].pose;
    const BasePose& b = r.path[i].pose;
    const double chord = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m);
    EXPECT_LE(chord, step + 1e-9) << i;
    EXPECT_GT(chord, 1e-6) << i;
    const double dyaw = planner::wrap_angle_rad(b.yaw_rad - a.yaw_rad);
    EXPECT_LE(std::abs(dyaw), 2.0 * std::asin(std::min(1.0, chord / (2.0 * radius))) + 1e-6) << i;
    const double heading = std::atan2(b.y_m - a.y_m, b.x_m - a.x_m) + (r.path[i].eta < 0 ? M_PI : 0.0);
    EXPECT_NEAR(planner::wrap_angle_rad(heading - a.yaw_rad - 0.5 * dyaw), 0.0, 1e-6) << i;
    // The straight chord between the waypoints is free as well.
    for (int k = 1; k < 10; ++k) {
      const double t = k / 10.0;
      const BasePose m{a.x_m + t * (b.x_m - a.x_m), a.y_m + t * (b.y_m - a.y_m), a.yaw_rad + t * dyaw};
      EXPECT_FALSE(f.exact.check_base(m).in_collision) << i;
    }
  }
  EXPECT_EQ(r.path.front().eta, r.path[1].eta);
}

TEST(HybridAStar, OpenFloorStraightShot) {
  Fixture f(test::open_scene_yaml());
  HybridAStar planner(f.model, f.exact);
  planner.set_map(f.grid);
  const HybridAStarResult r = planner.plan(f.scene.start, f.scene.goal, 10.0);
  expect_valid_base_path(r, f, planner.turning_radius_m(), planner.settings().step_length_m);
  EXPECT_TRUE(r.analytic_expansion);
  for (const auto& s : r.path) EXPECT_EQ(s.eta, 1);
  EXPECT_DOUBLE_EQ(planner.turning_radius_m(), f.model.base.min_turning_radius_m);
}

TEST(HybridAStar, TurnAroundNeedsArcsNotTurnsInPlace) {
  Fixture f(test::open_scene_yaml("[0.0, 0.0, 3.14159]"));
  HybridAStar planner(f.model, f.exact);
  planner.set_map(f.grid);
  const HybridAStarResult r = planner.plan(f.scene.start, f.scene.goal, 10.0);
  expect_valid_base_path(r, f, planner.turning_radius_m(), planner.settings().step_length_m);
  double travelled = 0.0;
  for (std::size_t i = 1; i < r.path.size(); ++i)
    travelled += std::hypot(r.path[i].pose.x_m - r.path[i - 1].pose.x_m, r.path[i].pose.y_m - r.path[i - 1].pose.y_m);
  EXPECT_GT(travelled, 0.4);  // a half turn on radius 0.4 cannot be shorter than a few decimetres
}

TEST(HybridAStar, DetoursThroughTheGap) {
  Fixture f(test::gap_scene_yaml());
  HybridAStar planner(f.model, f.exact);
  planner.set_map(f.grid);
  const HybridAStarResult r = planner.plan(f.scene.start, f.scene.goal, 30.0);
  expect_valid_base_path(r, f, planner.turning_radius_m(), planner.settings().step_length_m);
  double max_y = -1e9;
  for (const auto& s : r.path) max_y = std::max(max_y, s.pose.y_m);
  EXPECT_GT(max_y, 1.1);  // it went through the gap
  EXPECT_GT(r.report.iterations, 1);
  EXPECT_GT(r.report.collision_checks, 0);
}

TEST(HybridAStar, WalledOffGoalIsNoPath) {
  Fixture f(test::walled_goal_scene_yaml());
  HybridAStar planner(f.model, f.exact);
  planner.set_map(f.grid);
  const HybridAStarResult r = planner.plan(f.scene.start, f.scene.goal, 10.0);
  EXPECT_EQ(r.report.status, planner::Status::kNoPath);
  EXPECT_TRUE(r.path.empty());
}

TEST(HybridAStar, InvalidEndpointsAndTimeout) {
  Fixture f(test::gap_scene_yaml());
  HybridAStar planner(f.model, f.exact);
  planner.set_map(f.grid);
  RobotConfiguration in_wall = f.scene.start;
  in_wall.base = {2.5, -1.0, 0.0};
  EXPECT_EQ(planner.plan(in_wall, f.scene.goal, 1.0).report.status, planner::Status::kInvalidStart);
  EXPECT_EQ(planner.plan(f.scene.start, in_wall, 1.0).report.status, planner::Status::kInvalidGoal);
  const HybridAStarResult r = planner.plan(f.scene.start, f.scene.goal, 0.0);
  EXPECT_EQ(r.report.status, planner::Status::kTimeout);
  HybridAStar no_map(f.model, f.exact);
  EXPECT_EQ(no_map.plan(f.scene.start, f.scene.goal, 1.0).report.status, planner::Status::kNoMap);
}

TEST(HybridAStar, ReverseIsUsedWhenTheGoalIsBehind) {
  // Goal 1 m straight behind the start, same heading: reversing is the natural answer.
  Fixture f(test::open_scene_yaml("[-1.0, 0.0, 0.0]"));
  HybridAStar planner(f.model, f.exact);
  planner.set_map(f.grid);
  const HybridAStarResult r = planner.plan(f.scene.start, f.scene.goal, 10.0);
  expect_valid_base_path(r, f, planner.turning_radius_m(), planner.settings().step_length_m);
  bool reversed = false;
  for (const auto& s : r.path) reversed = reversed || s.eta < 0;
  EXPECT_TRUE(reversed);
}

TEST(HybridAStar, SameInputSamePath) {
  Fixture f(test::gap_scene_yaml());
  HybridAStar planner(f.model, f.exact);
  planner.set_map(f.grid);
  const HybridAStarResult a = planner.plan(f.scene.start, f.scene.goal, 30.0);
  const HybridAStarResult b = planner.plan(f.scene.start, f.scene.goal, 30.0);
  ASSERT_EQ(a.path.size(), b.path.size());
  for (std::size_t i = 0; i < a.path.size(); ++i) {
    EXPECT_EQ(a.path[i].pose.x_m, b.path[i].pose.x_m);
    EXPECT_EQ(a.path[i].pose.yaw_rad, b.path[i].pose.yaw_rad);
    EXPECT_EQ(a.path[i].eta, b.path[i].eta);
  }
  EXPECT_EQ(a.report.iterations, b.report.iterations);
}

TEST(HybridAStar, SettingsValidation) {
  HybridAStarSettings s;
  std::string why;
  EXPECT_TRUE(validate_settings(s, &why)) << why;
  s.steering_samples = 4;
  EXPECT_FALSE(validate_settings(s, &why));
  EXPECT_NE(why.find("steering_samples"), std::string::npos);
  s = HybridAStarSettings{};
  s.step_length_m = 0.1;  // shorter than the cell diagonal
  EXPECT_FALSE(validate_settings(s, &why));
}

}  // namespace
}  // namespace porter::frontend
