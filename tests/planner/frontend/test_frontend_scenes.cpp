// The front-end on the shipped scenes with the kernel checker: bridge (h_b 1.1 .. 0.8), tunnel
// and forest. Every node and edge is re-checked with the kernel checker and with the exact test
// checker; turning radius, joint limits and per-step joint speed limits are checked by
// check_path(). Budgets are iteration caps (the time budget is far away), so the results do not
// depend on machine speed.

#include <gtest/gtest.h>

#include "exact_checker.hpp"
#include "frontend_test_utils.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"
#include "test_scenes.hpp"

namespace porter::frontend {
namespace {

struct SceneFixture {
  SceneFixture(const Scene& s) : scene(s), model(fixed_model(scene)), grid(voxelize(scene)), kernel(model), exact(model, 0.02) {
    kernel.set_map(grid);
    exact.set_map(grid);
  }
  static RobotModel fixed_model(const Scene& scene) { return test::model_for(scene); }
  FrontendResult plan(std::uint64_t seed) {
    FrontendSettings s;
    s.layered_arm.max_iterations = 60000;
    s.whole_body_rrt.max_iterations = 4000;
    FrontEnd frontend(model, kernel, s);
    frontend.set_map(grid);
    radius = frontend.turning_radius_m();
    return frontend.plan(scene.start, scene.goal, 600.0, seed);
  }
  void expect_valid(const FrontendResult& r) {
    ASSERT_EQ(r.status, PlannerStatus::kSuccess) << r.message;
    test::PathCheckOptions opt;
    opt.turning_radius_m = radius;
    opt.start = &scene.start;
    opt.goal = &scene.goal;
    const auto errors = test::check_path(r.path, model, {&kernel, &exact}, opt);
    EXPECT_TRUE(errors.empty()) << errors.size() << " problems, first: " << errors.front();
  }
  Scene scene;
  RobotModel model;
  OccupancyGrid grid;
  planner::KernelCollisionChecker kernel;
  test::ExactCollisionChecker exact;
  double radius = 0.4;
};

Scene bridge(double h_b) {
  SceneLoadOptions o;
  o.parameter_overrides["h_b"] = h_b;
  return load_scene(test::scene_yaml("bridge"), o);
}

class BridgeSweep : public ::testing::TestWithParam<std::pair<double, std::uint64_t>> {};

TEST_P(BridgeSweep, PathThroughTheHole) {
  SceneFixture f(bridge(GetParam().first));
  f.expect_valid(f.plan(GetParam().second));
}

// Two seeds per clearance (success rates over 100 seeds: planner/app/README.md).
INSTANTIATE_TEST_SUITE_P(HbFrom1p1To0p8, BridgeSweep,
                         ::testing::Values(std::make_pair(1.1, 1), std::make_pair(1.1, 2), std::make_pair(1.0, 1),
                                           std::make_pair(1.0, 2), std::make_pair(0.9, 1), std::make_pair(0.9, 2),
                                           std::make_pair(0.8, 1), std::make_pair(0.8, 2)));

TEST(FrontendScenes, Tunnel) {
  SceneFixture f(load_scene(test::scene_yaml("tunnel")));
  f.expect_valid(f.plan(1));
}

TEST(FrontendScenes, Forest) {
  SceneLoadOptions o;
  o.seed = 3;
  SceneFixture f(load_scene(test::scene_yaml("forest"), o));
  f.expect_valid(f.plan(3));
}

TEST(FrontendScenes, WalledOffGoalIsNoPathWithTheKernelChecker) {
  SceneFixture f(test::scene_from_text(test::walled_goal_scene_yaml()));
  const FrontendResult r = f.plan(1);
  EXPECT_EQ(r.status, PlannerStatus::kNoPath) << r.message;
  EXPECT_TRUE(r.path.empty());
}

TEST(FrontendScenes, SameSeedSamePathOnTheBridge) {
  SceneFixture f(bridge(1.0));
  const FrontendResult a = f.plan(5);
  const FrontendResult b = f.plan(5);
  ASSERT_EQ(a.status, b.status);
  const auto fa = test::flatten(a.path), fb = test::flatten(b.path);
  ASSERT_EQ(fa.size(), fb.size());
  for (std::size_t i = 0; i < fa.size(); ++i) {
    EXPECT_TRUE(test::same_config(fa[i].node.config, fb[i].node.config, 0.0)) << i;
    EXPECT_EQ(fa[i].node.time_s, fb[i].node.time_s) << i;
  }
  EXPECT_EQ(a.layered_arm.iterations, b.layered_arm.iterations);
}

}  // namespace
}  // namespace porter::frontend
