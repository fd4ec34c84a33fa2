#pragma once
// Whole-body RRT* over (x, y, yaw, q1..q6): the front-end's fallback (paper §IV-A), used to
// bridge the gap the layered arm search could not connect and when Hybrid A* runs out of time.
//
// Steering: the base follows the shortest Reeds–Shepp curve (turning radius R, forward and
// reverse) truncated to max_extend_m; the joints move linearly in arc length (max_extend_q_rad
// per extension). An edge is sampled so that consecutive samples are at most edge_step_m
// apart along the curve and edge_q_step_rad apart in every joint (every cusp is a sample); it
// is valid when CollisionChecker::check_motion holds between all consecutive samples, which
// are exactly the nodes the path reports. Cost: Reeds–Shepp length with reverse stretches
// weighted by reverse_cost_factor, plus gear_switch_cost_m per cusp, + joint_cost_weight * |dq|
// (as in Hybrid A*: every gear switch is a segment joint of the mid-end).
// RRT*: the new node takes the cheapest valid parent among its `neighbours` nearest nodes and
// rewires them. Sampling: uniform over the start/goal box grown by sampling_margin_m (clipped
// to the map) and the joint limits until a solution exists, then informed: uniform in the
// prolate hyperspheroid over (x, y, w q) whose foci are start and goal and whose transverse
// diameter is the best cost (yaw uniform). Stops refine_iterations after the first solution,
// at max_iterations or at the time budget.
//
// Thread-safety: plan() is const and reentrant (it owns its Reeds–Shepp scratch).

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "porter/core/robot_model.hpp"
#include "porter/frontend/stage_report.hpp"
#include "porter/frontend/reeds_shepp.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/deadline.hpp"

namespace porter::frontend {

struct WholeBodyRrtSettings {
  /// Base arc length of one extension, m (> 0).
  double max_extend_m = 0.8;
  /// Largest joint change of one extension, rad (> 0).
  double max_extend_q_rad = 1.0;
  /// Multiplier on reverse arc length in the cost (>= 1).
  double reverse_cost_factor = 2.0;
  /// Cost of one direction change inside an edge, m-equivalent (>= 0).
  double gear_switch_cost_m = 1.0;
  /// Weight of the joint motion in the cost, m per rad (>= 0).
  double joint_cost_weight_m_per_rad = 0.2;
  /// Probability of sampling the goal [0, 1].
  double goal_bias = 0.1;
  /// Growth of the start/goal box that bounds uniform sampling, m (>= 0).
  double sampling_margin_m = 1.5;
  /// Nearest neighbours considered for choose-parent and rewiring (>= 1).
  int neighbours = 8;
  /// Largest chord between reported samples along an edge, m (> 0).
  double edge_step_m = 0.25;
  /// Largest joint change between reported samples, rad (> 0).
  double edge_q_step_rad = 0.3;
  /// Iterations spent improving after the first solution (>= 0).
  int refine_iterations = 100;
  /// Hard iteration cap (>= 1).
  std::int64_t max_iterations = 100000;
};

bool validate_settings(const WholeBodyRrtSettings& s, std::string* why);

/// A configuration on the path and the driving direction of the motion that reaches it.
struct WholeBodySample {
  RobotConfiguration config;
  int eta = 1;
};

struct WholeBodyRrtResult {
  StageReport report;
  std::vector<WholeBodySample> path;  ///< start ... goal (exact), on success
  double cost = 0.0;
};

class WholeBodyRrt {
 public:
  /// `map_bounds_xy_W` limits the base samples (the map's horizontal extent).
  WholeBodyRrt(const RobotModel& model, const planner::CollisionChecker& checker, double turning_radius_m,
               const Eigen::AlignedBox2d& map_bounds_xy_W, WholeBodyRrtSettings settings = {});
  const WholeBodyRrtSettings& settings() const { return settings_; }

  /// Plans until `deadline` expires (time up: kTimeout; canceled: kCanceled).
  WholeBodyRrtResult plan(const RobotConfiguration& start, const RobotConfiguration& goal,
                          const planner::Deadline& deadline, std::uint64_t seed) const;
  WholeBodyRrtResult plan(const RobotConfiguration& start, const RobotConfiguration& goal, double budget_s,
                          std::uint64_t seed) const {
    return plan(start, goal, planner::Deadline(budget_s), seed);
  }

 private:
  const RobotModel& model_;
  const planner::CollisionChecker& checker_;
  double radius_m_;
  Eigen::AlignedBox2d bounds_;
  WholeBodyRrtSettings settings_;
};

}  // namespace porter::frontend
