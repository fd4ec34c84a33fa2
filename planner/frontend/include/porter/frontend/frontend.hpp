#pragma once
// The front-end path search (paper §IV-A): Hybrid A* for the base, multilayer constrained
// RRT*-Connect for the arm along it, whole-body RRT* as the fallback, and the initial time
// allocation. Output: a WholeBodyPath whose segments have constant driving direction eta.
//
//   FrontEnd frontend(model, checker);       // checker: any CollisionChecker (kernels, ...)
//   checker.set_map(grid); frontend.set_map(grid);
//   FrontendResult r = frontend.plan(start, goal, /*budget_s=*/0.08, /*seed=*/7);
//   if (r.status == planner::Status::kSuccess) midend.solve(r.path, ...);
//
// Pipeline within one budget:
//   1. start and goal are validated: inside the map's horizontal bounds, finite, within the joint
//      limits and collision-free (whole body) — else kInvalidStart / kInvalidGoal;
//   2. Hybrid A* (at most hybrid_astar_budget_fraction of the budget). kNoPath ends the plan
//      with kNoPath (the base alone cannot get there). On a timeout the whole-body RRT* plans
//      from start to goal with the remaining budget;
//   3. the base waypoints become layers; layer times come from the base speed profile scaled by
//      arm_time_scale (at least min_layer_time_s); the layered arm search runs with
//      layered_arm_budget_fraction of the remaining budget;
//   4. if it cannot connect, the whole-body RRT* bridges the gap between the deepest node of
//      the start tree and the shallowest node of the goal tree (when the trees overlap without
//      connecting, two adjacent layers in the middle of the overlap), each end moved back by
//      bridge_margin_layers along its tree, with the rest of the budget;
//   5. the nodes get times (time_allocation.hpp) and are split into eta segments.
// Every node of a successful path is collision-free and every edge (straight line in
// [x, y, yaw, q] between consecutive nodes) passed CollisionChecker::check_motion.
//
// Results do not depend on machine speed as long as no stage hits the budget (stages stop on
// iteration counts after their first solution); same seed, same path.
//
// Thread-safety: one FrontEnd per thread (plan() reuses buffers); the checker must keep its
// map during plan(). Failure: a status and message in the result, never an exception.

#include <cstdint>
#include <string>

#include "porter/core/occupancy_grid.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/frontend/hybrid_astar.hpp"
#include "porter/frontend/layered_arm_planner.hpp"
#include "porter/frontend/stage_report.hpp"
#include "porter/frontend/time_allocation.hpp"
#include "porter/frontend/whole_body_rrt.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/deadline.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::frontend {

struct FrontendSettings {
  HybridAStarSettings hybrid_astar;
  LayeredArmSettings layered_arm;
  WholeBodyRrtSettings whole_body_rrt;
  TimeAllocationSettings time_allocation;
  /// Largest share of the budget Hybrid A* may use, (0, 1].
  double hybrid_astar_budget_fraction = 0.6;
  /// Share of the budget left after Hybrid A* that the layered arm search may use, (0, 1].
  double layered_arm_budget_fraction = 0.6;
  /// Layer time = base step time * this (> 0): the slack REMANI gives the arm between layers.
  double arm_time_scale = 3.0;
  /// Shortest layer time, s (> 0).
  double min_layer_time_s = 0.3;
  /// Layers each bridge end is moved back along its tree before the whole-body RRT* (>= 0).
  int bridge_margin_layers = 2;
};

bool validate_settings(const FrontendSettings& s, std::string* why);

struct FrontendResult {
  planner::Status status = planner::Status::kNoPath;
  std::string message;          ///< why it failed ("" on success)
  planner::WholeBodyPath path;  ///< on success
  double elapsed_s = 0.0;
  StageReport hybrid_astar;
  StageReport layered_arm;
  StageReport whole_body_rrt;
  int num_layers = 0;           ///< base waypoints from Hybrid A*
  bool used_fallback = false;   ///< the whole-body RRT* contributed to the path
};

class FrontEnd {
 public:
  FrontEnd(const RobotModel& model, const planner::CollisionChecker& checker, FrontendSettings settings = {});

  const FrontendSettings& settings() const { return settings_; }
  double turning_radius_m() const { return hybrid_astar_.turning_radius_m(); }

  /// Adopts a new map (the checker's map is set by its owner, before or after this call).
  void set_map(const OccupancyGrid& occupancy_W);

  /// Plans until `deadline` expires: time up gives kTimeout, a canceled deadline kCanceled.
  /// Statuses: kSuccess, kTimeout, kCanceled, kNoPath, kInvalidStart, kInvalidGoal, kNoMap.
  FrontendResult plan(const RobotConfiguration& start, const RobotConfiguration& goal,
                      const planner::Deadline& deadline, std::uint64_t seed);
  FrontendResult plan(const RobotConfiguration& start, const RobotConfiguration& goal, double budget_s,
                      std::uint64_t seed) {
    return plan(start, goal, planner::Deadline(budget_s), seed);
  }

 private:
  /// Empty string when the configuration is valid, otherwise why not.
  std::string validate_endpoint(const RobotConfiguration& c) const;

  const RobotModel& model_;
  const planner::CollisionChecker& checker_;
  FrontendSettings settings_;
  HybridAStar hybrid_astar_;
  LayeredArmPlanner layered_arm_;
  Eigen::AlignedBox2d map_xy_W_;
  bool have_map_ = false;
};

/// Splits samples into eta segments (sharing the gear-switch node) with the given step times.
planner::WholeBodyPath make_path(const std::vector<WholeBodySample>& samples, const std::vector<double>& step_times_s);

}  // namespace porter::frontend
