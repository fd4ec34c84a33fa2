// FrontEnd on small scenes with the exact test checker: valid paths, no_path for a walled-off
// goal, invalid endpoints with their reasons, budget exhaustion, determinism.

#include <gtest/gtest.h>

#include "exact_checker.hpp"
#include "frontend_test_utils.hpp"
#include "porter/frontend/frontend.hpp"
#include "test_scenes.hpp"

namespace porter::frontend {
namespace {

struct Fixture {
  explicit Fixture(const std::string& yaml)
      : scene(test::scene_from_text(yaml)), model(test::model_for(scene)), grid(voxelize(scene)), exact(model, 0.02),
        frontend(model, exact) {
    exact.set_map(grid);
    frontend.set_map(grid);
  }
  std::vector<std::string> check(const FrontendResult& r) {
    test::PathCheckOptions opt;
    opt.turning_radius_m = frontend.turning_radius_m();
    opt.start = &scene.start;
    opt.goal = &scene.goal;
    return test::check_path(r.path, model, {&exact}, opt);
  }
  Scene scene;
  RobotModel model;
  OccupancyGrid grid;
  test::ExactCollisionChecker exact;
  FrontEnd frontend;
};

TEST(FrontEnd, OpenFloor) {
  Fixture f(test::open_scene_yaml());
  const FrontendResult r = f.frontend.plan(f.scene.start, f.scene.goal, 30.0, 1);
  ASSERT_EQ(r.status, planner::Status::kSuccess) << r.message;
  const auto errors = f.check(r);
  EXPECT_TRUE(errors.empty()) << errors.front();
  EXPECT_TRUE(r.hybrid_astar.ran);
  EXPECT_TRUE(r.layered_arm.ran);
  EXPECT_FALSE(r.whole_body_rrt.ran);
  EXPECT_EQ(static_cast<std::size_t>(r.num_layers), r.path.node_count() - (r.path.segments.size() - 1));
}

TEST(FrontEnd, DetourWithArmChange) {
  Fixture f(test::gap_scene_yaml());
  f.scene.goal.q_rad[0] = 0.7;
  f.scene.goal.q_rad[5] = 1.2;
  const FrontendResult r = f.frontend.plan(f.scene.start, f.scene.goal, 60.0, 4);
  ASSERT_EQ(r.status, planner::Status::kSuccess) << r.message;
  const auto errors = f.check(r);
  EXPECT_TRUE(errors.empty()) << errors.front();
}

TEST(FrontEnd, ArmOnlyGoalUsesTheFallback) {
  Fixture f(test::open_scene_yaml("[0.0, 0.0, 0.0]"));
  f.scene.goal.q_rad[0] = 1.0;
  const FrontendResult r = f.frontend.plan(f.scene.start, f.scene.goal, 60.0, 2);
  ASSERT_EQ(r.status, planner::Status::kSuccess) << r.message;
  EXPECT_TRUE(r.used_fallback);
  const auto errors = f.check(r);
  EXPECT_TRUE(errors.empty()) << errors.front();
}

TEST(FrontEnd, WalledOffGoalIsNoPath) {
  Fixture f(test::walled_goal_scene_yaml());
  const FrontendResult r = f.frontend.plan(f.scene.start, f.scene.goal, 10.0, 1);
  EXPECT_EQ(r.status, planner::Status::kNoPath);
  EXPECT_TRUE(r.path.empty());
  EXPECT_NE(r.message.find("Hybrid A*"), std::string::npos);
}

TEST(FrontEnd, InvalidEndpointsAreReportedWithReasons) {
  Fixture f(test::gap_scene_yaml());
  RobotConfiguration c = f.scene.start;
  c.q_rad[1] = 3.5;  // joint 2 upper limit is 3.14
  FrontendResult r = f.frontend.plan(c, f.scene.goal, 1.0, 1);
  EXPECT_EQ(r.status, planner::Status::kInvalidStart);
  EXPECT_NE(r.message.find("joint 2"), std::string::npos) << r.message;
  c = f.scene.start;
  c.base = {2.5, -1.0, 0.0};  // inside the wall
  r = f.frontend.plan(f.scene.start, c, 1.0, 1);
  EXPECT_EQ(r.status, planner::Status::kInvalidGoal);
  EXPECT_NE(r.message.find("collision"), std::string::npos) << r.message;
  c.base = {50.0, 0.0, 0.0};
  r = f.frontend.plan(f.scene.start, c, 1.0, 1);
  EXPECT_EQ(r.status, planner::Status::kInvalidGoal);
  EXPECT_NE(r.message.find("outside the map"), std::string::npos) << r.message;
  c.base.x_m = std::nan("");
  EXPECT_EQ(f.frontend.plan(c, f.scene.goal, 1.0, 1).status, planner::Status::kInvalidStart);
}

TEST(FrontEnd, ExhaustedBudgetIsATimeout) {
  Fixture f(test::gap_scene_yaml());
  const FrontendResult r = f.frontend.plan(f.scene.start, f.scene.goal, 0.0, 1);
  EXPECT_EQ(r.status, planner::Status::kTimeout);
  EXPECT_TRUE(r.path.empty());
}

TEST(FrontEnd, NoMapIsNoMap) {
  Fixture f(test::open_scene_yaml());
  FrontEnd fresh(f.model, f.exact);
  EXPECT_EQ(fresh.plan(f.scene.start, f.scene.goal, 1.0, 1).status, planner::Status::kNoMap);
}

TEST(FrontEnd, SameSeedSamePath) {
  Fixture f(test::gap_scene_yaml());
  f.scene.goal.q_rad[0] = -0.6;
  const FrontendResult a = f.frontend.plan(f.scene.start, f.scene.goal, 60.0, 11);
  const FrontendResult b = f.frontend.plan(f.scene.start, f.scene.goal, 60.0, 11);
  ASSERT_EQ(a.status, planner::Status::kSuccess);
  ASSERT_EQ(a.path.segments.size(), b.path.segments.size());
  const auto fa = test::flatten(a.path), fb = test::flatten(b.path);
  ASSERT_EQ(fa.size(), fb.size());
  for (std::size_t i = 0; i < fa.size(); ++i) {
    EXPECT_TRUE(test::same_config(fa[i].node.config, fb[i].node.config, 0.0)) << i;
    EXPECT_EQ(fa[i].node.time_s, fb[i].node.time_s);
  }
}

TEST(FrontEnd, SettingsValidation) {
  FrontendSettings s;
  std::string why;
  EXPECT_TRUE(validate_settings(s, &why)) << why;
  s.layered_arm.goal_bias = 0.8;  // with local_bias 0.4 the probabilities exceed 1
  EXPECT_FALSE(validate_settings(s, &why));
  EXPECT_NE(why.find("local_bias"), std::string::npos) << why;
  s = FrontendSettings{};
  s.hybrid_astar_budget_fraction = 0.0;
  EXPECT_FALSE(validate_settings(s, &why));
  EXPECT_EQ(std::string(to_string(planner::Status::kNoPath)), "no_path");
  EXPECT_EQ(std::string(to_string(planner::Status::kInvalidGoal)), "invalid_goal");
}

}  // namespace
}  // namespace porter::frontend
