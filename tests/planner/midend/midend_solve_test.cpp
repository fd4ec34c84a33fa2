// End-to-end mid-end solves on synthetic front-end paths with reversals and arm motion, checked
// at 1 ms through porter::Trajectory (independent evaluation and wheel kinematics).
#include <gtest/gtest.h>

#include "porter/midend/midend.hpp"
#include "synthetic_paths.hpp"
#include "trajectory_checks.hpp"

namespace porter::midend {
namespace {

using testing::CheckReport;

struct NamedPath {
  const char* name;
  planner::WholeBodyPath (*make)();
};

planner::WholeBodyPath forest() { return testing::forest_slalom(50); }

class MidendSolveTest : public ::testing::TestWithParam<NamedPath> {};

TEST_P(MidendSolveTest, MeetsLimitsResidualsAndContinuity) {
  const planner::WholeBodyPath path = GetParam().make();
  MidendSettings settings;
  const MidEnd midend(testing::scout_mini_piper_model(), settings);
  // Generous budget: this test is about the optimum, not speed (no timing is asserted).
  const MidendResult r = midend.solve(path, 5.0);
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  EXPECT_TRUE(r.status == planner::Status::kConverged || r.status == planner::Status::kConvergedWithWarning)
      << to_string(r.status) << ": " << r.message;
  EXPECT_LT(r.final_cost.total(), r.initial_cost.total());
  EXPECT_TRUE(r.solution.has_value());

  const CheckReport c = testing::check_trajectory(*r.trajectory, path, midend.limits(), settings);
  EXPECT_TRUE(c.finite);
  EXPECT_LT(c.boundary_error, 1e-9);
  EXPECT_LT(c.continuity_error, 1e-7);
  EXPECT_LT(c.gear_error, 1e-7);
  EXPECT_LT(c.max_gear_yaw_jump_rad, 1e-3);
  EXPECT_LT(c.max_yaw_step_rad, 0.02);  // no jumps anywhere at 1 ms
  EXPECT_LE(c.wheel_velocity_ratio, 1.02);
  EXPECT_LE(c.wheel_acceleration_ratio, 1.02);
  EXPECT_LE(c.joint_velocity_ratio, 1.02);
  EXPECT_LE(c.joint_acceleration_ratio, 1.02);
  EXPECT_LE(c.joint_position_excess, 0.02);
  EXPECT_LE(c.residual_base_ratio, 1.02);
  EXPECT_LE(c.residual_arm_ratio, 1.02);
  // The rest-boundary heading term is an exact penalty (about w |angle|, midend_problem.cpp): the
  // optimum leaves the start and goal heading about delta F / w off (delta = 2 mrad, F the pull of
  // the other terms, F / w < 0.1 in the runs measured), far inside the 0.02 rad a goal pose is
  // asked to be reached within; 2 mrad is that bound with F = w.
  EXPECT_LT(c.start_heading_error_rad, 2e-3);
  EXPECT_LT(c.goal_heading_error_rad, 2e-3);
  std::printf("%s\n", r.message.c_str());
  std::printf("[%s] %s: pieces %d segs %d vars %d iters %d evals %d T %.2f s  %.1f ms\n"
              "  wheel w %.3f a %.3f joint v %.3f a %.3f q %.4f resid b %.3f m %.3f gear yaw %.2e"
              " heading %.2e/%.2e\n",
              GetParam().name, to_string(r.status), r.num_pieces, r.num_segments, r.num_variables,
              r.iterations, r.evaluations, r.trajectory->total_duration_s(), 1e3 * r.optimize_s,
              c.wheel_velocity_ratio, c.wheel_acceleration_ratio, c.joint_velocity_ratio,
              c.joint_acceleration_ratio, c.joint_position_excess, c.residual_base_ratio,
              c.residual_arm_ratio, c.max_gear_yaw_jump_rad, c.start_heading_error_rad,
              c.goal_heading_error_rad);
}

INSTANTIATE_TEST_SUITE_P(Paths, MidendSolveTest,
                         ::testing::Values(NamedPath{"forward_with_turn", testing::forward_with_turn},
                                           NamedPath{"three_point_turn", testing::three_point_turn},
                                           NamedPath{"forest_slalom", forest}),
                         [](const ::testing::TestParamInfo<NamedPath>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace porter::midend
