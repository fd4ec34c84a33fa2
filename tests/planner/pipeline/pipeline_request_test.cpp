// What the planner daemon asks for beyond a scene's start and goal: planning from a moving state
// (a hand-off onto the trajectory being executed), a goal pose with tolerances, a free arm.
#include <cmath>

#include <gtest/gtest.h>

#include "pipeline_fixtures.hpp"
#include "porter/planner/angle.hpp"

namespace porter::pipeline {
namespace {

TEST(PipelineRequest, PlanningFromAMovingStateContinuesItsVelocityAndAcceleration) {
  const Scene s = testing::scene("empty");
  Planner planner(testing::robot_for(s), testing::shipped_settings(s));
  ASSERT_TRUE(planner.set_map(voxelize(s)).ok);
  const PlanResult first = planner.plan(testing::request(s));
  ASSERT_EQ(first.status, planner::Status::kSuccess) << first.message;
  // Hand off a third of the way, while the base drives forward and the arm moves.
  const Trajectory& now = *first.trajectory;
  const StartState handoff = StartState::on_trajectory(now, now.total_duration_s() / 3.0);
  ASSERT_GT(handoff.velocity.head<2>().norm(), 0.05) << "the fixture must hand off while driving";
  PlanRequest req = testing::request(s);
  req.start = handoff;
  const PlanResult next = planner.plan(req);
  ASSERT_EQ(next.status, planner::Status::kSuccess) << next.message;
  const Trajectory& t = *next.trajectory;
  const TrajVector p0 = t.position(0.0);
  EXPECT_NEAR(p0[0], handoff.config.base.x_m, 1e-9);
  EXPECT_NEAR(p0[1], handoff.config.base.y_m, 1e-9);
  EXPECT_LT((p0.tail<kNumArmJoints>() - handoff.config.q_rad).norm(), 1e-9);
  EXPECT_LT((t.velocity(0.0) - handoff.velocity).norm(), 1e-9);
  EXPECT_LT((t.acceleration(0.0) - handoff.acceleration).norm(), 1e-9);
  EXPECT_NEAR(planner::angle_difference_rad(t.yaw_rad(0.0), handoff.config.base.yaw_rad), 0.0, 1e-9);
  // It still arrives at the goal, at rest.
  const TrajVector end = t.position(t.total_duration_s());
  EXPECT_NEAR(end[0], s.goal.base.x_m, 1e-6);
  EXPECT_LT(t.velocity(t.total_duration_s()).norm(), 1e-9);
}

// The caller's time (a daemon's hand-off seconds away) lengthens the back-end's budget when the
// stages before it leave more than the budget; less time, none, or NaN leave the budget as set.
// bridge h_b 1.1 seed 4: the mid-end's trajectory collides and the back-end runs (the recorded
// ablation seeds); a 1 ms back-end budget cannot finish it.
TEST(PipelineRequest, TheCallersTimeLengthensTheBackendBudget) {
  const Scene s = testing::scene("bridge", 1.1, 4);
  PlannerSettings settings = testing::shipped_settings(s);
  testing::generous_budgets(settings);
  settings.pipeline.backend_budget_s = 1e-3;
  Planner planner(testing::robot_for(s), settings);
  ASSERT_TRUE(planner.set_map(voxelize(s)).ok);
  for (const double t : {0.0, 1e-4, std::nan("")}) {
    PlanRequest req = testing::request(s);
    req.time_available_s = t;
    const PlanResult r = planner.plan(req);
    ASSERT_TRUE(r.backend.has_value()) << t << ": " << r.message;
    EXPECT_EQ(r.backend->budget_s, 1e-3) << t;
  }
  PlanRequest req = testing::request(s);
  req.time_available_s = 120.0;
  const PlanResult r = planner.plan(req);
  ASSERT_TRUE(r.backend.has_value()) << r.message;
  EXPECT_GT(r.backend->budget_s, 1e-3);
  EXPECT_LT(r.backend->budget_s, 120.0);
  EXPECT_EQ(r.backend->result.status, planner::Status::kConverged) << r.backend->result.message;
  EXPECT_EQ(r.status, planner::Status::kSuccess) << r.message;
}

TEST(PipelineRequest, AStartStateAgainstTheHeadingIsRefused) {
  const Scene s = testing::scene("empty");
  Planner planner(testing::robot_for(s), testing::shipped_settings(s));
  ASSERT_TRUE(planner.set_map(voxelize(s)).ok);
  PlanRequest req = testing::request(s);
  req.start.velocity[1] = 0.3;  // sideways: a diff-drive base cannot
  const PlanResult sideways = planner.plan(req);
  EXPECT_EQ(sideways.status, planner::Status::kInvalidStart);
  EXPECT_NE(sideways.message.find("heading"), std::string::npos) << sideways.message;
  // Backwards while the path to the goal ahead starts forward.
  req.start.velocity.setZero();
  req.start.velocity[0] = -0.3;
  const PlanResult reverse = planner.plan(req);
  EXPECT_EQ(reverse.status, planner::Status::kInvalidStart) << reverse.message;
}

TEST(PipelineRequest, AStartOffTheMapOrNotFiniteIsRefusedSayingSo) {
  const Scene s = testing::scene("empty");
  Planner planner(testing::robot_for(s), testing::shipped_settings(s));
  ASSERT_TRUE(planner.set_map(voxelize(s)).ok);
  PlanRequest req = testing::request(s);
  req.start.config.base.x_m = 1e4;  // far outside the map
  PlanResult r = planner.plan(req);
  EXPECT_EQ(r.status, planner::Status::kInvalidStart);
  EXPECT_NE(r.message.find("outside the map"), std::string::npos) << r.message;
  req = testing::request(s);
  req.start.config.base.yaw_rad = 1e11;  // never wrapped upstream
  r = planner.plan(req);
  EXPECT_EQ(r.status, planner::Status::kInvalidStart);
  EXPECT_NE(r.message.find("not a wrapped heading"), std::string::npos) << r.message;
  req = testing::request(s);
  req.start.config.q_rad[2] = std::nan("");
  r = planner.plan(req);
  EXPECT_EQ(r.status, planner::Status::kInvalidStart);
  EXPECT_NE(r.message.find("not finite"), std::string::npos) << r.message;
}

/// The empty scene with a wall across the map at x >= 8 + d (full height): the largest d (in
/// voxels) at which the scene's goal configuration (x = 8) touches it.
struct WallCase {
  OccupancyGrid grid;
  double d_m = 0.0;
};
WallCase wall_touching_goal(const Planner& planner, const Scene& s, const OccupancyGrid& open, const JointVector& arm) {
  for (int k = 30; k >= 0; --k) {
    OccupancyGrid g = open;
    const double x_wall = s.goal.base.x_m + k * s.resolution_m;
    for (int ix = 0; ix < g.dims().x(); ++ix) {
      if (g.voxel_center_W(ix, 0, 0).x() < x_wall) continue;
      for (int iy = 0; iy < g.dims().y(); ++iy)
        for (int iz = 0; iz < g.dims().z(); ++iz) g.set(ix, iy, iz);
    }
    planner::KernelCollisionChecker probe(planner.kernel_checker().robot());
    probe.set_map(g);
    RobotConfiguration goal = s.goal;
    goal.q_rad = arm;
    if (probe.check(goal).in_collision) return WallCase{g, k * s.resolution_m};
  }
  return WallCase{};
}

TEST(PipelineRequest, AnInvalidGoalPoseMovesWithinItsTolerance) {
  const Scene s = testing::scene("empty");
  Planner planner(testing::robot_for(s), testing::shipped_settings(s));
  const WallCase wall = wall_touching_goal(planner, s, voxelize(s), s.goal.q_rad);
  ASSERT_GT(wall.d_m, 0.0) << "no wall position touches the goal configuration";
  ASSERT_TRUE(planner.set_map(wall.grid).ok);
  PlanRequest req = testing::request(s, Stages::kFront);
  const PlanResult exact = planner.plan(req);  // zero tolerance: refused
  EXPECT_EQ(exact.status, planner::Status::kInvalidGoal) << exact.message;

  req.goal.position_tolerance_m = 0.2;
  req.goal.yaw_tolerance_rad = 0.1;
  const PlanResult moved = planner.plan(req);
  ASSERT_EQ(moved.status, planner::Status::kSuccess) << moved.message;
  EXPECT_TRUE(moved.goal.base_moved);
  EXPECT_FALSE(moved.goal.arm_chosen);
  const BasePose& g = moved.goal.config.base;
  EXPECT_LE(std::hypot(g.x_m - s.goal.base.x_m, g.y_m - s.goal.base.y_m), 0.2 + 1e-9);
  EXPECT_LE(std::abs(planner::angle_difference_rad(g.yaw_rad, s.goal.base.yaw_rad)), 0.1 + 1e-9);
  EXPECT_LT(g.x_m, s.goal.base.x_m);  // away from the wall
  EXPECT_FALSE(planner.frontend_checker().check(moved.goal.config).in_collision);
  // The path ends there.
  const planner::PathNode& last = moved.frontend->path.segments.back().nodes.back();
  EXPECT_NEAR(last.config.base.x_m, g.x_m, 1e-9);
  EXPECT_NEAR(last.config.base.y_m, g.y_m, 1e-9);
}

TEST(PipelineRequest, AFreeArmIsChosenValidTheStartsFirst) {
  const Scene s = testing::scene("empty");
  Planner planner(testing::robot_for(s), testing::shipped_settings(s));
  ASSERT_TRUE(planner.set_map(voxelize(s)).ok);
  PlanRequest req = testing::request(s, Stages::kFront);
  req.goal.arm_q_rad.reset();
  const PlanResult open = planner.plan(req);
  ASSERT_EQ(open.status, planner::Status::kSuccess) << open.message;
  EXPECT_TRUE(open.goal.arm_chosen);
  EXPECT_EQ(open.goal.config.q_rad, s.start.q_rad);  // the start's arm fits at the goal: kept
  EXPECT_EQ(open.goal.candidates, 1);

  // A wall the start's arm (with the payload) touches at the goal pose, which is kept exact:
  // another arm configuration is chosen.
  const WallCase wall = wall_touching_goal(planner, s, voxelize(s), s.start.q_rad);
  ASSERT_GT(wall.d_m, 0.0);
  ASSERT_TRUE(planner.set_map(wall.grid).ok);
  req.goal.position_tolerance_m = 0.0;
  req.goal.yaw_tolerance_rad = 0.0;
  const PlanResult chosen = planner.plan(req);
  ASSERT_EQ(chosen.goal.status, planner::Status::kSuccess) << chosen.goal.message;
  EXPECT_TRUE(chosen.goal.arm_chosen);
  EXPECT_FALSE(chosen.goal.base_moved);
  EXPECT_GT(chosen.goal.candidates, 1);
  EXPECT_NE(chosen.goal.config.q_rad, s.start.q_rad);
  EXPECT_TRUE(planner.model().within_joint_limits(chosen.goal.config.q_rad));
  EXPECT_FALSE(planner.frontend_checker().check(chosen.goal.config).in_collision);
}

}  // namespace
}  // namespace porter::pipeline
