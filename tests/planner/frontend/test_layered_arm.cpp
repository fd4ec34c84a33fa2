// Multilayer constrained RRT*-Connect: per-layer joint speed limits, whole-body validity of
// nodes and edges, endpoints, the payload turned under a low deck, failure modes, determinism.

#include <gtest/gtest.h>

#include "exact_checker.hpp"
#include "frontend_test_utils.hpp"
#include "porter/frontend/layered_arm_planner.hpp"
#include "test_scenes.hpp"

namespace porter::frontend {
namespace {

/// Layers every 0.25 m along y = 0 from x0 to x1, heading +x.
ArmLayerProblem straight_problem(double x0, double x1, double dt, const JointVector& qs, const JointVector& qg) {
  ArmLayerProblem p;
  const int n = static_cast<int>(std::round((x1 - x0) / 0.25)) + 1;
  for (int i = 0; i < n; ++i) p.bases.push_back({x0 + 0.25 * i, 0.0, 0.0});
  p.dt_s.assign(static_cast<std::size_t>(n - 1), dt);
  p.q_start = qs;
  p.q_goal = qg;
  return p;
}

void expect_valid(const LayeredArmResult& r, const ArmLayerProblem& p, const RobotModel& model,
                  const planner::CollisionChecker& checker, double speed_fraction) {
  ASSERT_EQ(r.report.status, planner::Status::kSuccess) << r.report.message;
  ASSERT_EQ(r.q.size(), p.bases.size());
  EXPECT_EQ(r.q.front(), p.q_start);
  EXPECT_EQ(r.q.back(), p.q_goal);
  const JointVector vmax = model.velocity_limits();
  double cost = 0.0;
  for (std::size_t i = 0; i < r.q.size(); ++i) {
    EXPECT_TRUE(model.within_joint_limits(r.q[i], 1e-12)) << i;
    EXPECT_FALSE(checker.check({p.bases[i], r.q[i]}).in_collision) << "layer " << i;
    if (i == 0) continue;
    const JointVector dq = (r.q[i] - r.q[i - 1]).cwiseAbs();
    EXPECT_TRUE((dq.array() <= speed_fraction * vmax.array() * p.dt_s[i - 1] * (1 + 1e-9)).all()) << "layer " << i;
    EXPECT_FALSE(checker.check_motion({p.bases[i - 1], r.q[i - 1]}, {p.bases[i], r.q[i]}).in_collision) << "edge " << i;
    cost += dq.sum();
  }
  EXPECT_NEAR(cost, r.cost, 1e-9);
}

struct Fixture {
  explicit Fixture(const Scene& s) : scene(s), model(test::model_for(scene)), grid(voxelize(scene)), exact(model, 0.02) {
    exact.set_map(grid);
  }
  Scene scene;
  RobotModel model;
  OccupancyGrid grid;
  test::ExactCollisionChecker exact;
};

TEST(LayeredArm, OpenFloorArmReconfiguresWithinSpeedLimits) {
  Fixture f(test::scene_from_text(test::open_scene_yaml()));
  JointVector qg = f.scene.start.q_rad;
  qg[0] = 1.2;   // turn the arm to the side
  qg[5] = -1.5;  // and roll the wrist
  const ArmLayerProblem p = straight_problem(0.0, 3.0, 0.4, f.scene.start.q_rad, qg);
  LayeredArmPlanner planner(f.model, f.exact);
  const LayeredArmResult r = planner.plan(p, 60.0, 1);
  expect_valid(r, p, f.model, f.exact, planner.settings().arm_speed_fraction);
  EXPECT_GT(r.report.iterations, 0);
}

TEST(LayeredArm, PayloadTurnsUnderTheLowDeck) {
  // Bridge hole of clearance 0.9 m at x = 0: the T bar's crossbar (vertical at the start pose,
  // reaching 1.09 m) must be turned to pass, and turned back before the goal.
  SceneLoadOptions options;
  options.parameter_overrides["h_b"] = 0.9;
  Fixture f(load_scene(test::scene_yaml("bridge"), options));
  const ArmLayerProblem p = straight_problem(-2.5, 2.5, 1.2, f.scene.start.q_rad, f.scene.goal.q_rad);
  bool blocked = false;  // the start pose does not fit under the deck somewhere
  for (const auto& b : p.bases) blocked = blocked || f.exact.check({b, p.q_start}).in_collision;
  ASSERT_TRUE(blocked);
  LayeredArmPlanner planner(f.model, f.exact);
  const LayeredArmResult r = planner.plan(p, 120.0, 3);
  expect_valid(r, p, f.model, f.exact, planner.settings().arm_speed_fraction);
}

TEST(LayeredArm, ShortcutsShortenTheArmMotionAndKeepEveryPromise) {
  // Same search (same seed) with and without the shortcut pass: the trees' solution is the same,
  // the shortcut one moves the arm less and still meets every per-layer promise.
  SceneLoadOptions options;
  options.parameter_overrides["h_b"] = 0.9;
  Fixture f(load_scene(test::scene_yaml("bridge"), options));
  const ArmLayerProblem p = straight_problem(-2.5, 2.5, 1.2, f.scene.start.q_rad, f.scene.goal.q_rad);
  LayeredArmSettings none;
  none.shortcut_attempts = 0;
  const LayeredArmResult raw = LayeredArmPlanner(f.model, f.exact, none).plan(p, 120.0, 5);
  const LayeredArmPlanner planner(f.model, f.exact);
  ASSERT_GT(planner.settings().shortcut_attempts, 0);
  const LayeredArmResult r = planner.plan(p, 120.0, 5);
  expect_valid(raw, p, f.model, f.exact, none.arm_speed_fraction);
  expect_valid(r, p, f.model, f.exact, planner.settings().arm_speed_fraction);
  EXPECT_EQ(r.report.iterations, raw.report.iterations);
  EXPECT_LT(r.cost, raw.cost - 1e-6) << "no shortcut was taken";
}

TEST(LayeredArm, TooLittleTimeBetweenLayersIsNoPath) {
  Fixture f(test::scene_from_text(test::open_scene_yaml()));
  JointVector qg = f.scene.start.q_rad;
  qg[0] = 1.5;
  // Two layers, 0.1 s apart: joint 1 cannot turn 1.5 rad; nothing to sample in between.
  ArmLayerProblem p = straight_problem(0.0, 0.25, 0.1, f.scene.start.q_rad, qg);
  LayeredArmPlanner planner(f.model, f.exact);
  const LayeredArmResult r = planner.plan(p, 10.0, 1);
  EXPECT_EQ(r.report.status, planner::Status::kNoPath);
  ASSERT_EQ(r.forward_q.size(), 1u);  // the frontiers are the roots
  ASSERT_EQ(r.backward_q.size(), 1u);
  EXPECT_EQ(r.forward_q[0], p.q_start);
  EXPECT_EQ(r.backward_q[0], p.q_goal);
}

TEST(LayeredArm, IterationCapIsATimeoutWithFrontiers) {
  // The walled goal layer cannot be reached: the search must stop at its cap.
  Fixture f(test::scene_from_text(test::open_scene_yaml()));
  JointVector qg = f.scene.start.q_rad;
  qg[0] = 2.5;
  ArmLayerProblem p = straight_problem(0.0, 1.0, 0.2, f.scene.start.q_rad, qg);  // 4 x 0.24 rad < 2.5 rad
  LayeredArmSettings s;
  s.max_iterations = 300;
  LayeredArmPlanner planner(f.model, f.exact, s);
  const LayeredArmResult r = planner.plan(p, 60.0, 1);
  EXPECT_EQ(r.report.status, planner::Status::kTimeout);
  EXPECT_EQ(r.report.iterations, 300);
  EXPECT_GE(r.forward_q.size(), 1u);
  EXPECT_GE(r.backward_q.size(), 1u);
  // The trees never reach the other end (they may overlap without connecting).
  EXPECT_LT(r.forward_q.size(), p.bases.size());
  EXPECT_LT(r.backward_q.size(), p.bases.size());
  EXPECT_EQ(r.forward_q.front(), p.q_start);
  EXPECT_EQ(r.backward_q.back(), p.q_goal);
}

TEST(LayeredArm, InvalidEndpointsAndMalformedProblems) {
  Fixture f(test::scene_from_text(test::gap_scene_yaml()));
  LayeredArmPlanner planner(f.model, f.exact);
  ArmLayerProblem p = straight_problem(0.0, 1.0, 0.5, f.scene.start.q_rad, f.scene.start.q_rad);
  p.bases.back() = {2.5, -1.0, 0.0};  // inside the wall
  EXPECT_EQ(planner.plan(p, 1.0, 1).report.status, planner::Status::kInvalidGoal);
  p.bases.back() = {1.0, 0.0, 0.0};
  p.dt_s.pop_back();
  EXPECT_EQ(planner.plan(p, 1.0, 1).report.status, planner::Status::kNoPath);
}

TEST(LayeredArm, SameSeedSameResult) {
  Fixture f(test::scene_from_text(test::open_scene_yaml()));
  JointVector qg = f.scene.start.q_rad;
  qg[0] = -1.0;
  qg[3] = 1.0;
  const ArmLayerProblem p = straight_problem(0.0, 3.0, 0.4, f.scene.start.q_rad, qg);
  LayeredArmPlanner planner(f.model, f.exact);
  const LayeredArmResult a = planner.plan(p, 60.0, 5);
  const LayeredArmResult b = planner.plan(p, 60.0, 5);
  ASSERT_EQ(a.report.status, planner::Status::kSuccess);
  ASSERT_EQ(a.q.size(), b.q.size());
  for (std::size_t i = 0; i < a.q.size(); ++i) EXPECT_EQ(a.q[i], b.q[i]);
  EXPECT_EQ(a.report.iterations, b.report.iterations);
}

}  // namespace
}  // namespace porter::frontend
