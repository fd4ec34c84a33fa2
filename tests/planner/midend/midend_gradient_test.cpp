// Every analytic gradient of the mid-end cost (each term separately and all together, on
// waypoints, times and gear-switch variables) against central finite differences, at random
// points around synthetic front-end paths where the penalties are active.
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_problem.hpp"
#include "porter/midend/reference_path.hpp"
#include "porter/minco/time_map.hpp"
#include "synthetic_paths.hpp"

namespace porter::midend {
namespace {

struct TermCase {
  const char* name;
  std::uint32_t mask;
};

const TermCase kTerms[] = {
    {"energy", kTermEnergy},
    {"time", kTermTime},
    {"wheel_velocity", kTermWheelVelocity},
    {"wheel_acceleration", kTermWheelAcceleration},
    {"joint_position", kTermJointPosition},
    {"joint_velocity", kTermJointVelocity},
    {"joint_acceleration", kTermJointAcceleration},
    {"residual_base", kTermResidualBase},
    {"residual_arm", kTermResidualArm},
    {"boundary_heading", kTermBoundaryHeading},
    {"min_speed", kTermMinSpeed},
    {"all", kTermAll},
};

/// Limits tightened so that every penalty is active somewhere at the perturbed points.
MidendLimits tight_limits() {
  MidendLimits l = MidendLimits::from_robot(testing::scout_mini_piper_model());
  l.wheel_omega_max_radps = 4.0;
  l.wheel_alpha_max_radps2 = 0.2;  // low enough that the rest-boundary limits are violated
  l.joint_velocity_max_radps.setConstant(0.15);
  l.joint_acceleration_max_radps2.setConstant(0.2);
  l.joint_upper_rad[1] = 1.25;  // carry pose has q2 = 1.2
  l.joint_lower_rad[4] = 0.45;  // and q5 = 0.5
  return l;
}

struct BlockErrors {
  double all = 0.0, waypoints = 0.0, times = 0.0, gears = 0.0;
};

double rel(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double floor = 1e-6) {
  const double scale = std::max(b.norm(), floor);
  return (a - b).norm() / scale;
}

void check(const planner::WholeBodyPath& path, unsigned seed, const char* label, bool require_active = true,
           const StartDerivatives& start = {}) {
  MidendSettings settings;
  settings.residual_base_bound_m = 0.25;
  settings.residual_arm_bound_rad = 0.2;
  const MidendLimits limits = tight_limits();
  ReferenceBuild ref = build_reference_path(path, limits, settings, start);
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  MidendProblem problem(ref.path, limits, settings);
  const int n = problem.num_variables();

  // Which variables are waypoints / times / gear states (by re-deriving the layout).
  std::vector<int> kind(n, 0);  // 0 waypoint, 1 time, 2 gear
  {
    int o = 0;
    for (const auto& seg : ref.path.segments) {
      o += kTrajDim * (seg.num_pieces() - 1);
      for (int i = 0; i < seg.num_pieces(); ++i) kind[o++] = 1;
    }
    for (; o < n - 1; ++o) kind[o] = 2;
    kind[n - 1] = 1;  // the global time scale
  }

  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 1; ++trial) {
    Eigen::VectorXd x = problem.initial_guess();
    // Uniform 0.5 s pieces: brisker than the speed-profile guess, so that the rest-boundary wheel
    // limits are violated too.
    for (int k = 0; k + 1 < n; ++k) {
      if (kind[k] == 1) x[k] = minco::tau_from_duration(0.5);
    }
    for (int k = 0; k < n; ++k) x[k] += (kind[k] == 1 ? 0.4 : 0.15) * u(rng);
    // Slow the gear switches' neighbourhood down so that the non-singular speed is violated.
    x[n - 1] += 0.2;
    if (require_active) {
      // The rest-boundary wheel term (exact limits at v = a = 0) must be exercised too: core's
      // Trajectory evaluates the same limits at t = 0 and at the goal.
      const TrajectoryResult tr = Trajectory::create(problem.pieces(x.data()), problem.start_yaw_rad());
      ASSERT_TRUE(tr.ok());
      const double t_end = tr.trajectory->total_duration_s();
      const WheelRates w0 = tr.trajectory->sample(0.0, limits.track_width_m, limits.wheel_radius_m).wheels;
      const WheelRates w1 = tr.trajectory->sample(t_end, limits.track_width_m, limits.wheel_radius_m).wheels;
      EXPECT_GT(std::max({std::abs(w0.left_radps2), std::abs(w0.right_radps2), std::abs(w1.left_radps2),
                          std::abs(w1.right_radps2)}),
                limits.wheel_alpha_max_radps2)
          << label << ": the rest-boundary wheel term is not active";
    }
    for (const TermCase& t : kTerms) {
      problem.set_terms(t.mask);
      Eigen::VectorXd g(n);
      CostBreakdown b;
      const double f = problem.evaluate(x, &g, &b);
      ASSERT_TRUE(std::isfinite(f)) << t.name;
      const bool can_be_inactive =
          (t.mask == kTermMinSpeed && ref.path.segments.size() == 1) ||  // rest pieces only
          (t.mask == kTermMinSpeed && ref.path.num_pieces() <= 2);
      if (require_active && !can_be_inactive) {
        EXPECT_GT(f, 0.0) << label << " " << t.name << ": term inactive, the test would be vacuous";
      }
      Eigen::VectorXd fd(n);
      for (int k = 0; k < n; ++k) {
        const double h = 1e-6 * std::max(1.0, std::abs(x[k]));
        // Fourth-order central difference: truncation O(h^4), so the stiff penalties do not
        // dominate the comparison.
        Eigen::VectorXd xs = x;
        auto f_at = [&](double dx) {
          xs[k] = x[k] + dx;
          return problem.evaluate(xs, nullptr, nullptr);
        };
        fd[k] = (-f_at(2 * h) + 8 * f_at(h) - 8 * f_at(-h) + f_at(-2 * h)) / (12.0 * h);
      }
      EXPECT_LT(rel(g, fd), 1e-5) << label << " " << t.name;
      for (int kd = 0; kd < 3; ++kd) {
        std::vector<int> idx;
        for (int k = 0; k < n; ++k) if (kind[k] == kd) idx.push_back(k);
        if (idx.empty()) continue;
        Eigen::VectorXd ga(idx.size()), gf(idx.size());
        for (std::size_t k = 0; k < idx.size(); ++k) {
          ga[k] = g[idx[k]];
          gf[k] = fd[idx[k]];
        }
        if (gf.norm() < 1e-6 * std::max(1.0, fd.norm())) continue;  // block not affected by this term
        // Blocks that carry under 0.1 % of the gradient are compared relative to that floor
        // (their own norm is at the level of the finite-difference noise).
        EXPECT_LT(rel(ga, gf, 1e-3 * fd.norm()), 1e-5) << label << " " << t.name << " block " << kd;
      }
    }
  }
}

TEST(MidendGradient, ForwardWithTurn) { check(testing::forward_with_turn(), 11, "forward_with_turn"); }
TEST(MidendGradient, ThreePointTurnWithGearSwitches) { check(testing::three_point_turn(), 12, "three_point_turn"); }
TEST(MidendGradient, ReverseOnly) {
  testing::PathBuilder b({0.5, 0.5, 1.0}, testing::carry_pose());
  JointVector q = testing::carry_pose();
  q[0] = 0.5;
  b.arm_to(q).arc(1.0, 0.8, -1).straight(1.0, -1);
  check(b.build(), 13, "reverse_only", false);
}
TEST(MidendGradient, StillEndsWithRestJunctions) {
  // The arm moves alone at the start and at the goal: still segments at both ends, joined to the
  // driving segment by rest junctions (reference_path.hpp, step 5b).
  JointVector q1 = testing::carry_pose(), q2 = testing::carry_pose();
  q1[0] = 0.6;
  q2[0] = -0.4;
  q2[3] = 0.5;
  testing::PathBuilder b({0.0, 0.0, 0.3}, testing::carry_pose());
  b.arm_only(q1).straight(1.5, 1).arc(1.2, 0.6, 1).arm_only(q2);
  const planner::WholeBodyPath path = b.build();
  const MidendLimits limits = tight_limits();
  const ReferenceBuild ref = build_reference_path(path, limits, MidendSettings{});
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(ref.path.segments.size(), 3u);
  EXPECT_TRUE(ref.path.segments.front().base_still);
  EXPECT_TRUE(ref.path.segments.back().base_still);
  check(path, 15, "still_ends", false);  // the rest boundaries are inside, not at t = 0 and the goal
}
TEST(MidendGradient, MovingStart) {
  // A hand-off while moving: the base leaves the first node at 0.4 m/s along its heading and
  // accelerating, the arm turning; the first piece has no rest-boundary terms then.
  const planner::WholeBodyPath path = testing::forward_with_turn();
  const double yaw = path.segments.front().nodes.front().config.base.yaw_rad;
  StartDerivatives start;
  start.velocity << 0.4 * std::cos(yaw), 0.4 * std::sin(yaw), 0.1, -0.05, 0.0, 0.08, 0.0, 0.0;
  start.acceleration << 0.2 * std::cos(yaw), 0.2 * std::sin(yaw), 0.0, 0.05, -0.02, 0.0, 0.0, 0.0;
  check(path, 16, "moving_start", false, start);
}
TEST(MidendGradient, TwoNodes) {
  testing::PathBuilder b({0.0, 0.0, 0.2}, testing::carry_pose(), 2.0);
  b.straight(1.0, 1);
  check(b.build(), 14, "two_nodes", false);
}

}  // namespace
}  // namespace porter::midend
