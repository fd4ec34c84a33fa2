// Time allocation and path assembly: speed and acceleration caps, stops at gear switches, arm
// speed limits, segments sharing their gear-switch node.

#include <gtest/gtest.h>

#include "frontend_test_utils.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/frontend/time_allocation.hpp"

namespace porter::frontend {
namespace {

const RobotModel& model() {
  static const RobotModel m = load_robot_model(test::robot_yaml());
  return m;
}

std::vector<WholeBodySample> straight(int n, double step, int eta) {
  std::vector<WholeBodySample> s;
  for (int i = 0; i < n; ++i) s.push_back({{{eta * step * i, 0.0, 0.0}, JointVector::Zero()}, eta});
  return s;
}

TEST(TimeAllocation, StraightRunRespectsSpeedAndAcceleration) {
  const TimeAllocationSettings st;
  const auto samples = straight(41, 0.25, 1);  // 10 m
  const std::vector<double> dt = whole_body_step_times(model(), samples, st);
  ASSERT_EQ(dt.size(), 40u);
  const double vmax = st.base_speed_fraction * model().base.wheel_omega_max_radps * model().base.wheel_radius_m;
  const double amax = st.base_accel_fraction * model().base.wheel_alpha_max_radps2 * model().base.wheel_radius_m;
  double total = 0.0;
  for (double t : dt) {
    EXPECT_GE(0.25 / t, 0.0);
    EXPECT_LE(0.25 / t, vmax * (1 + 1e-9));  // mean speed of every step under the cap
    total += t;
  }
  // Rest to rest: at least length / vmax + vmax / amax (the ramps), and not much more.
  EXPECT_GE(total, 10.0 / vmax + vmax / amax - 1e-9);
  EXPECT_LE(total, 10.0 / vmax + vmax / amax + 0.05);
  EXPECT_NEAR(dt.front(), dt.back(), 1e-9);  // symmetric profile
  EXPECT_GT(dt.front(), dt[20]);             // slow at the ends
}

TEST(TimeAllocation, GearSwitchStopsTheBase) {
  const TimeAllocationSettings st;
  std::vector<WholeBodySample> s = straight(9, 0.25, 1);
  for (int i = 1; i <= 8; ++i) s.push_back({{{2.0 - 0.25 * i, 0.0, 0.0}, JointVector::Zero()}, -1});
  const std::vector<double> dt = whole_body_step_times(model(), s, st);
  const double amax = st.base_accel_fraction * model().base.wheel_alpha_max_radps2 * model().base.wheel_radius_m;
  // The steps into and out of the cusp start/end at rest: each takes at least sqrt(2 s / a).
  EXPECT_GE(dt[7], std::sqrt(2.0 * 0.25 / amax) - 1e-9);
  EXPECT_GE(dt[8], std::sqrt(2.0 * 0.25 / amax) - 1e-9);
  EXPECT_GT(dt[7], dt[4]);
}

TEST(TimeAllocation, CurvatureSlowsTheBaseAndTheArmSetsItsOwnTime) {
  const TimeAllocationSettings st;
  std::vector<WholeBodySample> arc;
  BasePose p{0, 0, 0};
  for (int i = 0; i < 30; ++i) {
    arc.push_back({{p, JointVector::Zero()}, 1});
    p = drive_arc(p, 1.0 / 0.4, 0.25);
  }
  const auto line = straight(30, 0.25, 1);
  const auto t_arc = whole_body_step_times(model(), arc, st);
  const auto t_line = whole_body_step_times(model(), line, st);
  EXPECT_GT(t_arc[15], t_line[15]);
  // A pure arm step: joint 1 turns 1 rad with the base at rest.
  std::vector<WholeBodySample> arm = {{{{0, 0, 0}, JointVector::Zero()}, 1}, {{{0, 0, 0}, JointVector::Zero()}, 1}};
  arm[1].config.q_rad[0] = 1.0;
  const auto t_arm = whole_body_step_times(model(), arm, st);
  EXPECT_NEAR(t_arm[0], 1.0 / (st.joint_speed_fraction * model().joints[0].velocity_max_radps), 1e-12);
}

TEST(TimeAllocation, StepArcRecoversLengthAndCurvature) {
  const BasePose a{0.3, -0.2, 0.7};
  const BasePose b = drive_arc(a, 1.0 / 0.5, 0.4);
  double len = 0.0, kappa = 0.0;
  step_arc(a, b, &len, &kappa);
  EXPECT_NEAR(len, 0.4, 1e-9);
  EXPECT_NEAR(kappa, 2.0, 1e-9);
}

TEST(MakePath, SegmentsShareTheGearSwitchNode) {
  std::vector<WholeBodySample> s = straight(4, 0.25, 1);                                  // 0 .. 0.75
  for (int i = 1; i <= 3; ++i) s.push_back({{{0.75 - 0.25 * i, 0.0, 0.0}, JointVector::Zero()}, -1});  // back to 0
  s.push_back({{{0.25, 0.0, 0.0}, JointVector::Zero()}, 1});
  const std::vector<double> dt(s.size() - 1, 0.5);
  const planner::WholeBodyPath path = make_path(s, dt);
  ASSERT_EQ(path.segments.size(), 3u);
  EXPECT_EQ(path.segments[0].eta, 1);
  EXPECT_EQ(path.segments[1].eta, -1);
  EXPECT_EQ(path.segments[2].eta, 1);
  EXPECT_EQ(path.segments[0].nodes.size(), 4u);
  EXPECT_EQ(path.segments[1].nodes.size(), 4u);
  EXPECT_EQ(path.segments[2].nodes.size(), 2u);
  EXPECT_EQ(path.node_count(), s.size() + 2);
  for (std::size_t k = 1; k < path.segments.size(); ++k) {
    EXPECT_TRUE(test::same_config(path.segments[k - 1].nodes.back().config, path.segments[k].nodes.front().config, 0.0));
    EXPECT_EQ(path.segments[k - 1].nodes.back().time_s, path.segments[k].nodes.front().time_s);
  }
  EXPECT_DOUBLE_EQ(path.segments.back().nodes.back().time_s, 0.5 * (s.size() - 1));
}

}  // namespace
}  // namespace porter::frontend
