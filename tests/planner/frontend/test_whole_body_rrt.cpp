// Whole-body RRT*: valid whole-body paths (Reeds–Shepp base motion, joint interpolation), pure
// arm motions, the budget, invalid endpoints, determinism.

#include <gtest/gtest.h>

#include "exact_checker.hpp"
#include "frontend_test_utils.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/frontend/whole_body_rrt.hpp"
#include "test_scenes.hpp"

namespace porter::frontend {
namespace {

struct Fixture {
  explicit Fixture(const std::string& yaml)
      : scene(test::scene_from_text(yaml)), model(test::model_for(scene)), grid(voxelize(scene)), exact(model, 0.02) {
    exact.set_map(grid);
    const Eigen::AlignedBox3d b = grid.bounds_W();
    box = Eigen::AlignedBox2d(b.min().head<2>(), b.max().head<2>());
  }
  Scene scene;
  RobotModel model;
  OccupancyGrid grid;
  test::ExactCollisionChecker exact;
  Eigen::AlignedBox2d box;
};

planner::WholeBodyPath as_path(const RobotModel& model, const WholeBodyRrtResult& r) {
  return make_path(r.path, whole_body_step_times(model, r.path, TimeAllocationSettings{}));
}

TEST(WholeBodyRrt, SidewaysGoalWithArmChange) {
  Fixture f(test::open_scene_yaml());
  RobotConfiguration goal = f.scene.start;
  goal.base = {1.5, 1.2, M_PI / 2};
  goal.q_rad[0] = 0.8;
  WholeBodyRrt rrt(f.model, f.exact, 0.4, f.box);
  const WholeBodyRrtResult r = rrt.plan(f.scene.start, goal, 60.0, 2);
  ASSERT_EQ(r.report.status, planner::Status::kSuccess) << r.report.message;
  EXPECT_GT(r.cost, std::hypot(1.5, 1.2) - 1e-9);
  test::PathCheckOptions opt;
  opt.start = &f.scene.start;
  opt.goal = &goal;
  const auto errors = test::check_path(as_path(f.model, r), f.model, {&f.exact}, opt);
  EXPECT_TRUE(errors.empty()) << errors.front();
}

TEST(WholeBodyRrt, PureArmMotionKeepsTheBase) {
  Fixture f(test::open_scene_yaml());
  RobotConfiguration goal = f.scene.start;
  goal.q_rad[0] = -1.0;
  goal.q_rad[5] = 1.0;
  WholeBodyRrt rrt(f.model, f.exact, 0.4, f.box);
  const WholeBodyRrtResult r = rrt.plan(f.scene.start, goal, 60.0, 2);
  ASSERT_EQ(r.report.status, planner::Status::kSuccess) << r.report.message;
  test::PathCheckOptions opt;
  opt.start = &f.scene.start;
  opt.goal = &goal;
  const auto errors = test::check_path(as_path(f.model, r), f.model, {&f.exact}, opt);
  EXPECT_TRUE(errors.empty()) << errors.front();
}

TEST(WholeBodyRrt, BudgetAndInvalidEndpoints) {
  Fixture f(test::walled_goal_scene_yaml());
  WholeBodyRrtSettings s;
  s.max_iterations = 50;
  WholeBodyRrt rrt(f.model, f.exact, 0.4, f.box, s);
  const WholeBodyRrtResult r = rrt.plan(f.scene.start, f.scene.goal, 60.0, 1);
  EXPECT_EQ(r.report.status, planner::Status::kTimeout);  // enclosed goal: the cap ends it
  EXPECT_EQ(r.report.iterations, 50);
  EXPECT_TRUE(r.path.empty());
  RobotConfiguration in_wall = f.scene.start;
  in_wall.base = {3.5, 0.0, 0.0};
  EXPECT_EQ(rrt.plan(in_wall, f.scene.goal, 1.0, 1).report.status, planner::Status::kInvalidStart);
  EXPECT_EQ(rrt.plan(f.scene.start, in_wall, 1.0, 1).report.status, planner::Status::kInvalidGoal);
}

TEST(WholeBodyRrt, SameSeedSamePath) {
  Fixture f(test::open_scene_yaml());
  RobotConfiguration goal = f.scene.start;
  goal.base = {1.0, -1.0, -1.0};
  WholeBodyRrt rrt(f.model, f.exact, 0.4, f.box);
  const WholeBodyRrtResult a = rrt.plan(f.scene.start, goal, 60.0, 9);
  const WholeBodyRrtResult b = rrt.plan(f.scene.start, goal, 60.0, 9);
  ASSERT_EQ(a.report.status, planner::Status::kSuccess);
  ASSERT_EQ(a.path.size(), b.path.size());
  for (std::size_t i = 0; i < a.path.size(); ++i) EXPECT_TRUE(test::same_config(a.path[i].config, b.path[i].config, 0.0));
}

}  // namespace
}  // namespace porter::frontend
