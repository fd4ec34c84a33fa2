// Regression: the front-end reaches the goal with a last edge that moves the base ~2.5 mm while
// the arm turns ~0.9 rad (forest seeds 6 and 9 of scripts/bench-midend). Timed by the arm, the
// edge asked the base to creep; the quintic entering it at speed overshot the goal and reversed
// inside the segment, and the result broke the wheel and yaw checks while reporting "converged".
// Now the tail is a still segment (reference_path.hpp, step 5b): the base comes to rest at the
// goal, then the arm finishes. The same at the start. And whatever the settings, a trajectory
// that breaks the checked properties is never returned as a success.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "porter/midend/midend.hpp"
#include "porter/midend/reference_path.hpp"
#include "synthetic_paths.hpp"
#include "trajectory_checks.hpp"

namespace porter::midend {
namespace {

planner::PathNode node_at(const planner::PathNode& from, double dx_m, const JointVector& q, double dt_s) {
  planner::PathNode n = from;
  n.config.base.x_m += dx_m * std::cos(from.config.base.yaw_rad);
  n.config.base.y_m += dx_m * std::sin(from.config.base.yaw_rad);
  n.config.q_rad = q;
  n.time_s += dt_s;
  return n;
}

/// A forward drive of `length_m` from `start` in the carry pose, then one more node dx_m further
/// and dt_s later with joint `joint` (0-based) turned by dq_rad.
planner::WholeBodyPath drive_then_turn_joint(const BasePose& start, double length_m, int joint, double dq_rad,
                                             double dx_m, double dt_s) {
  testing::PathBuilder b(start, testing::carry_pose(), 0.25);
  b.straight(length_m, 1);
  planner::WholeBodyPath path = b.build();
  auto& nodes = path.segments.front().nodes;
  JointVector q = nodes.back().config.q_rad;
  q[joint] += dq_rad;
  nodes.push_back(node_at(nodes.back(), dx_m, q, dt_s));
  return path;
}

/// A 3 m forward drive whose last edge moves the base 2.5 mm and joint 1 by 0.9 rad; with
/// `creep_at_start`, the first edge does the same.
planner::WholeBodyPath creeping_path(bool creep_at_start) {
  planner::WholeBodyPath path = drive_then_turn_joint({1.0, -0.5, 0.2}, 3.0, 0, 0.9, 0.0025, 0.02);
  auto& nodes = path.segments.front().nodes;
  if (creep_at_start) {
    // Shift the drive by 2 mm and start from a node 2 mm behind with the arm 0.9 rad away.
    for (auto& n : nodes) n.time_s += 0.02;
    JointVector q0 = nodes.front().config.q_rad;
    q0[0] -= 0.9;
    nodes.insert(nodes.begin(), node_at(nodes.front(), -0.002, q0, -0.02));
  }
  return path;
}

std::string describe(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& line : v) s += "\n  " + line;
  return s;
}

void expect_still_end(bool creep_at_start) {
  const planner::WholeBodyPath path = creeping_path(creep_at_start);
  const MidEnd midend(testing::scout_mini_piper_model());
  const ReferenceBuild ref = build_reference_path(path, midend.limits(), midend.settings());
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(ref.path.segments.size(), creep_at_start ? 3u : 2u);
  const ReferenceSegment& tail = ref.path.segments.back();
  EXPECT_TRUE(tail.base_still);
  EXPECT_EQ(tail.eta, 1);
  for (const RobotConfiguration& n : tail.nodes) {  // held at the goal's base pose
    EXPECT_EQ(n.base.x_m, path.segments.back().nodes.back().config.base.x_m);
    EXPECT_EQ(n.base.y_m, path.segments.back().nodes.back().config.base.y_m);
  }
  EXPECT_EQ(ref.path.segments.front().base_still, creep_at_start);

  const MidendResult r = midend.solve(path, 10.0);
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  EXPECT_TRUE(r.status == planner::Status::kConverged || r.status == planner::Status::kConvergedWithWarning)
      << to_string(r.status);
  const testing::CheckReport k = testing::check_trajectory(*r.trajectory, path, midend.limits(), midend.settings());
  const std::vector<std::string> v = testing::violations(k);
  EXPECT_TRUE(v.empty()) << describe(v);
  EXPECT_EQ(k.reversals, 0);
  EXPECT_EQ(k.gear_switches, 0);
  EXPECT_EQ(k.rest_junctions, creep_at_start ? 2 : 1);
  // The base is exactly still over the arm-only tail, and the arm does move there.
  const Trajectory& t = *r.trajectory;
  const TrajectoryPiece& last = t.piece(t.num_pieces() - 1);
  EXPECT_EQ(last.coeffs.col(0).tail<kTrajDegree>().cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(last.coeffs.col(1).tail<kTrajDegree>().cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(last.coeffs.col(2).tail<kTrajDegree>().cwiseAbs().maxCoeff(), 0.0);
}

TEST(MidendStillEnd, CreepingLastEdgeRestsTheBaseAtTheGoalWhileTheArmFinishes) { expect_still_end(false); }

TEST(MidendStillEnd, CreepingFirstAndLastEdges) { expect_still_end(true); }

// Regression (tunnel seed 13 of scripts/bench-midend): the arm finishes at the goal with a
// 1.64 rad turn of joint 4 over 5 cm of base path, densified into four 0.41 rad edges. Timed at
// constant joint speed, those edges had equal durations, so the node before the goal sat at
// 3/4 of the still tail's time while the arm, braking to rest, got there much earlier and then
// crept: the residual to the node nearest in time reached 1.05 rho_m. The still tail is now
// timed with the joints' acceleration ramps (reference_path.hpp, step 7).
planner::WholeBodyPath arm_finish_path() { return drive_then_turn_joint({0.0, 0.0, 0.0}, 2.0, 3, 1.64, 0.05, 0.5); }

TEST(MidendStillEnd, ArmFinishIsTimedWithAccelerationRampsAndKeepsTheResidual) {
  const planner::WholeBodyPath path = arm_finish_path();
  const MidEnd midend(testing::scout_mini_piper_model());
  const MidendSettings& st = midend.settings();
  const ReferenceBuild ref = build_reference_path(path, midend.limits(), st);
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(ref.path.segments.size(), 2u);
  const ReferenceSegment& tail = ref.path.segments.back();
  ASSERT_TRUE(tail.base_still);
  const int edges = static_cast<int>(tail.nodes.size()) - 1;
  ASSERT_GE(edges, 4);  // 1.64 rad in parts of at most densify_factor * rho_m
  // Edge durations from the pieces and the node fractions inside them.
  std::vector<double> edge_s;
  for (int p = 0; p < tail.num_pieces(); ++p) {
    for (int k = 0; k < tail.edges_in_piece(p); ++k) {
      edge_s.push_back((tail.fraction_in_piece(p, k + 1) - tail.fraction_in_piece(p, k)) * tail.durations_s[p]);
    }
  }
  ASSERT_EQ(static_cast<int>(edge_s.size()), edges);
  // Braking to rest: the last edge lasts at least sqrt(2 d / a) (d: its joint-4 motion, a: the
  // reduced acceleration bound), longer than the constant-speed d / v, and longer than an edge
  // in the middle of the motion.
  const double f = st.initial_speed_fraction;
  const double d = std::abs(tail.nodes[edges].q_rad[3] - tail.nodes[edges - 1].q_rad[3]);
  const double a = f * midend.limits().joint_acceleration_max_radps2[3];
  const double v = f * midend.limits().joint_velocity_max_radps[3];
  EXPECT_GE(edge_s.back(), std::sqrt(2.0 * d / a) * (1.0 - 0.1));  // fractions are on a grid
  EXPECT_GT(edge_s.back(), 1.5 * d / v);
  EXPECT_GT(edge_s.back(), 1.2 * edge_s[static_cast<std::size_t>(edges / 2)]);

  const MidendResult r = midend.solve(path, 10.0);
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  const testing::CheckReport k = testing::check_trajectory(*r.trajectory, path, midend.limits(), st);
  const std::vector<std::string> v_list = testing::violations(k);
  EXPECT_TRUE(v_list.empty()) << describe(v_list);
  EXPECT_LE(k.residual_arm_ratio, 1.02);
}

// Regression (forest seed 17 after the front-end change of 9712b01): the last front-end edge moves
// the base 2 mm and not the arm. Kept as a reference node, the quintic through it overshot the
// goal and came back; the node is now dropped (reference_path.hpp, step 5a).
TEST(MidendStillEnd, MillimetreLastEdgeWithoutArmMotionIsDropped) {
  testing::PathBuilder b({0.0, 0.0, 0.0}, testing::carry_pose(), 0.25);
  b.straight(3.0, 1);
  planner::WholeBodyPath path = b.build();
  auto& nodes = path.segments.front().nodes;
  const planner::PathNode goal = node_at(nodes.back(), 0.002, nodes.back().config.q_rad, 0.01);
  nodes.push_back(goal);
  const MidEnd midend(testing::scout_mini_piper_model());
  const ReferenceBuild ref = build_reference_path(path, midend.limits(), midend.settings());
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(ref.path.segments.size(), 1u);
  const auto& rn = ref.path.segments.front().nodes;
  ASSERT_GE(rn.size(), 2u);
  EXPECT_EQ(rn.back().base.x_m, goal.config.base.x_m);  // the goal itself stays
  const RobotConfiguration& before = rn[rn.size() - 2];
  EXPECT_GT(std::hypot(goal.config.base.x_m - before.base.x_m, goal.config.base.y_m - before.base.y_m), 0.1);

  const MidendResult r = midend.solve(path, 10.0);
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  const testing::CheckReport k = testing::check_trajectory(*r.trajectory, path, midend.limits(), midend.settings());
  const std::vector<std::string> v = testing::violations(k);
  EXPECT_TRUE(v.empty()) << describe(v);
  EXPECT_EQ(k.reversals, 0);
}

TEST(MidendStillEnd, WithoutStillEndsNoWrongTrajectoryIsReturned) {
  // The pre-fix behaviour (still ends disabled): either a trajectory that passes the checks or
  // a clear status without one, never a "converged" trajectory that reverses.
  MidendSettings settings;
  settings.still_max_base_m = 0.0;
  const planner::WholeBodyPath path = creeping_path(false);
  const MidEnd midend(testing::scout_mini_piper_model(), settings);
  const ReferenceBuild ref = build_reference_path(path, midend.limits(), settings);
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(ref.path.segments.size(), 1u);
  const MidendResult r = midend.solve(path, 10.0);
  if (r.ok()) {
    const testing::CheckReport k = testing::check_trajectory(*r.trajectory, path, midend.limits(), settings);
    testing::CheckTolerances tol;
    tol.limit_ratio = 1.0 + settings.verify_tolerance;  // the library's own rejection bound
    tol.joint_position_excess = settings.verify_tolerance;
    EXPECT_EQ(k.reversals, 0);
    for (const std::string& line : testing::violations(k, tol)) {
      EXPECT_EQ(line.find("limit"), std::string::npos) << line;
    }
  } else {  // a clear status (on this path: the line search stalls without progress)
    EXPECT_FALSE(r.trajectory.has_value());
    EXPECT_FALSE(r.message.empty()) << to_string(r.status);
  }
}

TEST(MidendStillEnd, VerificationRejectsAGrossViolation) {
  // Limits far below what the path needs at any sensible duration, a tiny iteration cap: the
  // optimizer cannot fix them, so the result check must reject the trajectory.
  MidendLimits limits = MidendLimits::from_robot(testing::scout_mini_piper_model());
  limits.joint_velocity_max_radps.setConstant(1e-3);
  limits.joint_acceleration_max_radps2.setConstant(1e-3);
  MidendSettings settings;
  settings.max_iterations = 2;
  const MidEnd midend(limits, settings);
  const MidendResult r = midend.solve(creeping_path(false), 10.0);
  EXPECT_EQ(r.status, planner::Status::kConstraintViolation) << to_string(r.status) << ": " << r.message;
  EXPECT_FALSE(r.ok());
  EXPECT_FALSE(r.trajectory.has_value());
  EXPECT_NE(r.message.find("rejected"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace porter::midend
