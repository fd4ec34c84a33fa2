#pragma once
// Hybrid A* for the base on (x, y, yaw) (paper §IV-A; Dolgov et al.).
//
// Motion primitives are arcs of length step_length_m driven forward or in reverse with
// curvatures evenly spread over [-1/R, 1/R] (R = turning radius; never a turn in place, since
// the trajectory model ties the yaw to the velocity direction). Each primitive is accepted when
// the base is collision-free (CollisionChecker::check_base) along the arc and along the straight
// chord between its end poses (the chord is what the arm search's whole-body edge checks
// interpolate). Arcs are sampled so that no point of the base moves more than collision_step_m
// between samples (translation plus the base's reach times the heading change); chords at the
// poses the kernel checker's motion check visits with the arm held (the whole body's reach in
// place of the base's, collision_step_m = its motion step, one voxel): with sparser chord
// samples a 2-3 cm graze of a tree passed here and then failed every arm edge between the two
// layers (forest: 1 seed in 5 left the layered search unable to connect). Shots are checked along the curve (coarse-to-fine) and
// along every chord between their output waypoints.
// Costs: arc length, times reverse_cost_factor in reverse, plus gear_switch_cost_m per change
// of direction, small steering terms, and a guidance term where the whole body collides at the
// start's arm configuration, at the goal's and at a narrow carrying shape chosen once per plan
// (arm_blocked_cost_factor; soft, since the arm planner may still find a configuration that
// fits). Heuristic: max of the obstacle-free
// Reeds–Shepp distance (within rs_heuristic_range_m of the goal, Euclidean beyond) and the
// grid distance around obstacles (GridHeuristic, rebuilt by set_map()). Every expansion close
// to the goal (and every analytic_expansion_interval-th one elsewhere) tries a Reeds–Shepp shot
// to the exact goal pose; the search ends with the first collision-free shot.
//
// The result is the base path sampled at most step_length_m apart (one sample per primitive);
// these samples become the layers of the arm planner.
//
// Thread-safety: one object per thread (plan() reuses internal buffers). The checker must not
// change its map during plan(). Failure: a status in the result, never an exception.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "porter/core/occupancy_grid.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/frontend/grid_heuristic.hpp"
#include "porter/frontend/stage_report.hpp"
#include "porter/frontend/reeds_shepp.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/deadline.hpp"

namespace porter::frontend {

struct HybridAStarSettings {
  /// Cell size of the (x, y) search lattice, m (0.02 .. 1).
  double xy_resolution_m = 0.1;
  /// Heading bins of the lattice (8 .. 360).
  int yaw_bins = 72;
  /// Arc length of one motion primitive and spacing of the output waypoints, m (> xy cell
  /// diagonal so that every primitive leaves its cell).
  double step_length_m = 0.25;
  /// Curvature samples per direction, odd (3 .. 15); the middle one is straight.
  int steering_samples = 5;
  /// Turning radius of primitives and shots, m; the model's min_turning_radius_m is used when
  /// this is smaller.
  double turning_radius_m = 0.0;
  /// Largest base-point displacement between collision checks along arcs, chords and shots, m
  /// (0.005 .. 0.5); the kernel checker's motion step (one voxel) keeps chords consistent with
  /// the arm search's motion checks (see the header comment).
  double collision_step_m = 0.05;
  /// Multiplier on reverse arc length (>= 1).
  double reverse_cost_factor = 2.0;
  /// Cost of one change of driving direction, m-equivalent (>= 0).
  double gear_switch_cost_m = 1.0;
  /// Cost per metre at full curvature, scaled by |kappa| R (>= 0).
  double steering_cost = 0.1;
  /// Cost per change of curvature, scaled by |delta kappa| R (>= 0).
  double steering_change_cost = 0.1;
  /// Weighted A*: f = g + w h (>= 1; 1 keeps the heuristic admissible). The guidance cost
  /// (arm_blocked_cost_factor) is not in the heuristic, so a low weight explores widely around
  /// blocked stretches: forest, 100 seeds, 200 ms front-end budget: w = 1.5 -> 98 %, median
  /// 48 ms, p97 158 ms; w = 2 -> 100 %, 22 ms, 60 ms (tunnel median 10.6-12.6 -> 9.4 ms).
  double heuristic_weight = 2.0;
  /// Beyond this Euclidean distance to the goal the Reeds–Shepp part of the heuristic is
  /// replaced by the Euclidean distance (cheaper, nearly equal far away), m.
  double rs_heuristic_range_m = 4.0;
  /// Shots are tried at every expansion whose grid distance to the goal is below this, m.
  double analytic_expansion_range_m = 5.0;
  /// ... and at every n-th expansion elsewhere (>= 1).
  int analytic_expansion_interval = 10;
  /// Shots with more direction changes than this are rejected (0 .. 3).
  int max_shot_cusps = 1;
  /// Check the whole body at the start's and goal's arm configurations at every new node and
  /// add arm_blocked_cost_factor per metre where both collide.
  bool whole_body_guidance = true;
  /// 3 per metre with the narrow shape below: forest (200 ms, 100 seeds) 93 % success, against
  /// 84-86 % with 1 and no narrow shape; bridge and tunnel unchanged.
  double arm_blocked_cost_factor = 3.0;
  /// A third guidance shape, the narrowest (smallest lateral reach of the arm and payload
  /// bounding spheres) of this many seeded random arm configurations that fit at the start
  /// (0: none). A node is penalized only where it does not fit either: a start shape held
  /// across the driving direction collides in every narrow gap and guides nowhere.
  int narrow_shape_draws = 300;
  /// Cell size of the grid heuristic, m.
  double heuristic_resolution_m = 0.1;
  /// Hard cap on expansions (the time budget usually ends the search first).
  std::int64_t max_expansions = 500000;
};

/// Checks the documented ranges; false with *why naming the first bad field.
bool validate_settings(const HybridAStarSettings& s, std::string* why);

struct HybridAStarResult {
  StageReport report;
  /// Base waypoints from start to goal (exact end poses). eta of a sample is the direction of
  /// the motion that reaches it; the first sample carries the direction of the first motion.
  std::vector<BaseSample> path;
  bool analytic_expansion = false;  ///< the path ends with a Reeds–Shepp shot
};

class HybridAStar {
 public:
  HybridAStar(const RobotModel& model, const planner::CollisionChecker& checker,
              HybridAStarSettings settings = {});
  ~HybridAStar();

  const HybridAStarSettings& settings() const { return settings_; }
  double turning_radius_m() const { return radius_m_; }

  /// Adopts the map's horizontal extent and rebuilds the grid heuristic's obstacle cells. Call
  /// after (or together with) the checker's own set_map().
  void set_map(const OccupancyGrid& occupancy_W);

  /// The grid heuristic of the last set_map() (goal of the last plan()).
  const GridHeuristic& grid_heuristic() const { return grid_; }

  /// Searches a base path from start.base to goal.base until `deadline` expires (time up: kTimeout;
  /// canceled: kCanceled). The arm configurations are used only for the whole-body guidance.
  /// Requires set_map().
  HybridAStarResult plan(const RobotConfiguration& start, const RobotConfiguration& goal,
                         const planner::Deadline& deadline);
  HybridAStarResult plan(const RobotConfiguration& start, const RobotConfiguration& goal, double budget_s) {
    return plan(start, goal, planner::Deadline(budget_s));
  }

 private:
  struct Search;
  /// settings_.narrow_shape_draws seeded arm configurations, narrowest first (built once).
  std::vector<JointVector> narrow_shape_candidates() const;
  /// The narrowest candidate fitting at `at`.
  std::optional<JointVector> narrow_shape(const BasePose& at, StageReport& rep) const;

  const RobotModel& model_;
  const planner::CollisionChecker& checker_;
  HybridAStarSettings settings_;
  double radius_m_;
  InscribedDisc disc_;
  double base_reach_m_ = 0.0;   ///< horizontal reach of the base geometry (arc sampling)
  double chord_reach_m_ = 0.0;  ///< whole-body reach (chord sampling, as the arm search's checks)
  GridHeuristic grid_;
  bool have_map_ = false;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> stamp_;
  std::vector<std::int32_t> cell_node_;
  std::uint32_t generation_ = 0;
  std::unique_ptr<ReedsShepp> rs_;
  std::vector<JointVector> narrow_candidates_;
};

}  // namespace porter::frontend
