// Degenerate and invalid inputs: a result or a clear status, never NaN; the solution the mid-end
// hands the back-end; budget, cancellation and iteration-cap statuses.
#include <cmath>

#include <gtest/gtest.h>

#include "porter/midend/lbfgs_codes.hpp"
#include "porter/midend/midend.hpp"
#include "porter/midend/midend_problem.hpp"
#include "synthetic_paths.hpp"
#include "trajectory_checks.hpp"

namespace porter::midend {
namespace {

planner::PathNode node(double x, double y, double yaw, double t, double q0 = 0.0) {
  planner::PathNode n;
  n.config.base = {x, y, yaw};
  n.config.q_rad = testing::carry_pose();
  n.config.q_rad[0] = q0;
  n.time_s = t;
  return n;
}

MidEnd make_midend(MidendSettings s = {}) { return MidEnd(testing::scout_mini_piper_model(), s); }

/// Solves and checks the common contract: a usable trajectory with exact boundaries, no NaN,
/// limits within 2 %.
void expect_good(const planner::WholeBodyPath& path, const char* label) {
  const MidEnd m = make_midend();
  const MidendResult r = m.solve(path, 5.0);
  ASSERT_TRUE(r.ok()) << label << ": " << to_string(r.status) << " " << r.message;
  const testing::CheckReport c = testing::check_trajectory(*r.trajectory, path, m.limits(), m.settings());
  EXPECT_TRUE(c.finite) << label;
  EXPECT_LT(c.boundary_error, 1e-9) << label;
  EXPECT_LT(c.continuity_error, 1e-7) << label;
  EXPECT_LE(c.wheel_velocity_ratio, 1.02) << label;
  EXPECT_LE(c.wheel_acceleration_ratio, 1.02) << label;
  EXPECT_LE(c.joint_velocity_ratio, 1.02) << label;
  EXPECT_LE(c.joint_acceleration_ratio, 1.02) << label;
  EXPECT_LE(c.residual_base_ratio, 1.02) << label;
  EXPECT_LE(c.residual_arm_ratio, 1.02) << label;
  EXPECT_TRUE(std::isfinite(r.final_cost.total())) << label;
}

TEST(MidendDegenerate, TwoNodePath) {
  planner::WholeBodyPath p;
  p.segments = {{1, {node(0, 0, 0.2, 0), node(0.35 * std::cos(0.2), 0.35 * std::sin(0.2), 0.2, 1.0)}}};
  expect_good(p, "two nodes");
}

TEST(MidendDegenerate, ReverseOnlyPath) {
  testing::PathBuilder b({0.5, 0.5, 1.0}, testing::carry_pose());
  JointVector q = testing::carry_pose();
  q[0] = 0.5;
  b.arm_to(q).arc(1.0, 0.8, -1).straight(1.0, -1);
  const planner::WholeBodyPath p = b.build();
  ASSERT_EQ(p.segments.size(), 1u);
  ASSERT_EQ(p.segments[0].eta, -1);
  expect_good(p, "reverse only");
}

TEST(MidendDegenerate, CoincidentNodes) {
  planner::WholeBodyPath p;
  p.segments = {{1, {node(0, 0, 0, 0), node(0, 0, 0, 0), node(0.4, 0, 0, 1), node(0.4, 0, 0, 1),
                     node(0.8, 0, 0, 2), node(0.8, 0, 0, 2)}}};
  expect_good(p, "coincident nodes");
}

TEST(MidendDegenerate, ZeroLengthSegments) {
  planner::WholeBodyPath p;
  p.segments = {{1, {node(0, 0, 0, 0), node(0.4, 0, 0, 1)}},
                {-1, {node(0.4, 0, 0, 1), node(0.4, 0, 0, 1)}},
                {1, {node(0.4, 0, 0, 1), node(0.8, 0, 0, 2), node(1.2, 0, 0, 3)}},
                {-1, {node(1.2, 0, 0, 3)}}};
  expect_good(p, "zero-length segments");
}

TEST(MidendDegenerate, AllNodesCoincideGivesStationaryTrajectory) {
  planner::WholeBodyPath p;
  p.segments = {{1, {node(1, 2, 0.5, 0), node(1, 2, 0.5, 1)}}};
  const MidendResult r = make_midend().solve(p, 0.1);
  ASSERT_EQ(r.status, planner::Status::kTrivialPath) << r.message;
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(r.trajectory->position(0.0)[0], 1.0, 1e-12);
  EXPECT_NEAR(r.trajectory->position(r.trajectory->total_duration_s())[1], 2.0, 1e-12);
  EXPECT_TRUE(r.trajectory->velocity(0.0).isZero());
  EXPECT_NEAR(r.trajectory->yaw_rad(0.0), 0.5, 1e-12);
}

TEST(MidendDegenerate, InvalidInputsHaveClearStatus) {
  const MidEnd m = make_midend();
  MidendResult r = m.solve({}, 0.1);
  EXPECT_EQ(r.status, planner::Status::kInvalidInput);
  EXPECT_FALSE(r.ok());
  EXPECT_FALSE(r.message.empty());

  planner::WholeBodyPath p;
  p.segments = {{1, {node(0, 0, 0, 0), node(std::nan(""), 0, 0, 1)}}};
  r = m.solve(p, 0.1);
  EXPECT_EQ(r.status, planner::Status::kInvalidInput);
  EXPECT_NE(r.message.find("non-finite"), std::string::npos);

  p.segments = {{0, {node(0, 0, 0, 0), node(1, 0, 0, 1)}}};
  EXPECT_EQ(m.solve(p, 0.1).status, planner::Status::kInvalidInput);
}

TEST(MidendDegenerate, InvalidRobotLimits) {
  RobotModel robot = testing::scout_mini_piper_model();
  robot.base.wheel_radius_m = 0.0;
  const MidendResult r = MidEnd(robot).solve(testing::forward_with_turn(), 0.1);
  EXPECT_EQ(r.status, planner::Status::kInvalidRobotLimits);
  EXPECT_NE(r.message.find("wheel_radius"), std::string::npos);
  robot = testing::scout_mini_piper_model();
  robot.joints[2].upper_rad = robot.joints[2].lower_rad;
  EXPECT_EQ(MidEnd(robot).solve(testing::forward_with_turn(), 0.1).status, planner::Status::kInvalidRobotLimits);
}

TEST(MidendDegenerate, InvalidSettings) {
  MidendSettings s;
  s.samples_per_piece = 1;
  const MidendResult r = make_midend(s).solve(testing::forward_with_turn(), 0.1);
  EXPECT_EQ(r.status, planner::Status::kInvalidInput);
  EXPECT_NE(r.message.find("samples_per_piece"), std::string::npos);
}

TEST(MidendSolution, TheSolutionDescribesTheReturnedTrajectory) {
  const MidEnd m = make_midend();
  const MidendResult r = m.solve(testing::forward_with_turn(), 5.0);
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(r.solution.has_value());
  // The same problem at the handed-over decision vector gives the returned trajectory.
  MidendProblem problem(r.solution->reference, m.limits(), r.solution->settings);
  ASSERT_EQ(r.solution->x.size(), problem.num_variables());
  const std::vector<TrajectoryPiece> pieces = problem.pieces(r.solution->x.data());
  ASSERT_EQ(static_cast<int>(pieces.size()), r.trajectory->num_pieces());
  for (int i = 0; i < r.trajectory->num_pieces(); ++i) {
    EXPECT_NEAR(pieces[static_cast<std::size_t>(i)].duration_s, r.trajectory->piece(i).duration_s, 1e-9);
    EXPECT_LT((pieces[static_cast<std::size_t>(i)].coeffs - r.trajectory->piece(i).coeffs).norm(),
              1e-6 * (1.0 + r.trajectory->piece(i).coeffs.norm()));
  }
  // ... and solution_for() recovers it from the path and the trajectory alone.
  const std::optional<MidendSolution> again = m.solution_for(testing::forward_with_turn(), *r.trajectory);
  ASSERT_TRUE(again.has_value());
  EXPECT_LT((again->x - r.solution->x).norm(), 1e-9 * (1.0 + r.solution->x.norm()));
  EXPECT_GE(r.elapsed_s, r.optimize_s + r.prepare_s);
  // No solution without a problem to solve.
  const MidendResult empty = m.solve({}, 5.0);
  EXPECT_FALSE(empty.solution.has_value());
}

TEST(MidendExecution, ACanceledDeadlineStopsTheSolveWithoutATrajectory) {
  planner::CancelFlag cancel;
  cancel.request();
  const MidendResult r = make_midend().solve(testing::forest_slalom(50), planner::Deadline(60.0, &cancel));
  EXPECT_EQ(r.status, planner::Status::kCanceled) << r.message;
  EXPECT_FALSE(r.trajectory.has_value());
  EXPECT_FALSE(r.solution.has_value());
  EXPECT_LE(r.iterations, 1);
}

TEST(MidendExecution, TimeBudgetAndIterationCapReturnTheLastIterate) {
  MidendResult r = make_midend().solve(testing::forest_slalom(50), 1e-6);
  EXPECT_EQ(r.status, planner::Status::kTimeout) << r.message;
  EXPECT_TRUE(r.ok());
  EXPECT_LE(r.iterations, 1);

  MidendSettings s;
  s.max_iterations = 3;
  r = make_midend(s).solve(testing::forward_with_turn(), 5.0);
  EXPECT_TRUE(r.status == planner::Status::kIterationLimit || r.status == planner::Status::kConvergedWithWarning)
      << to_string(r.status);
  EXPECT_TRUE(r.ok());
  EXPECT_LE(r.iterations, 3);
  EXPECT_LE(r.final_cost.total(), r.initial_cost.total());
}

TEST(MidendStatusStrings, EveryValueHasAName) {
  for (planner::Status st : {planner::Status::kConverged, planner::Status::kConvergedWithWarning,
                          planner::Status::kIterationLimit, planner::Status::kTimeout,
                          planner::Status::kTrivialPath, planner::Status::kInvalidInput,
                          planner::Status::kInvalidRobotLimits, planner::Status::kNumericalFailure,
                          planner::Status::kOptimizerFailed, planner::Status::kCanceled}) {
    EXPECT_STRNE(to_string(st), "unknown");
  }
  EXPECT_STREQ(lbfgs_code_to_string(12345), "unknown lbfgs code");
  EXPECT_STRNE(lbfgs_code_to_string(-1001), "unknown lbfgs code");
}

}  // namespace
}  // namespace porter::midend
