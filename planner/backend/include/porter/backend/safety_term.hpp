#pragma once
// The back-end's collision term, as an interface so that the paper's ablations are one flag each:
//   kc_svsdf        (ours)      SvsdfSafetyTerm with the KinematicFilter   (svsdf_safety_term.hpp)
//   svsdf_per_link  (ablation)  SvsdfSafetyTerm without it                 (planner/baselines)
//   spheres         (baseline)  bounding spheres against an ESDF           (planner/baselines)
// The back-end adds the term's cost to the mid-end problem and its gradient, given with respect to
// the raw trajectory parameters (trajectory_gradient.hpp), to the MINCO adjoint.
//
// Thread-safety: a term is used by one solve at a time (workspaces inside).

#include <limits>
#include <string>

#include "porter/backend/trajectory_gradient.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/trajectory.hpp"

namespace porter::backend {

/// What one evaluation looked at (for the result and the benchmark).
struct SafetyStats {
  int obstacle_points = 0;     ///< points (or robot spheres) the term holds after prepare()
  int candidate_points = 0;    ///< passing the AABB prefilter in this evaluation
  int link_queries = 0;        ///< (point, link) distances computed
  int violations = 0;          ///< of those, closer than the safety margin
  int inside = 0;              ///< of those, negative
  double min_distance_m = std::numeric_limits<double>::infinity();  ///< over computed pairs
  double cost = 0.0;
  double time_s = 0.0;         ///< wall time of evaluate()
  double prefilter_s = 0.0;    ///< of which the prefilter (choosing the candidate points), if the term has one
  /// Some link certainly meets an occupied map voxel (or a voxel under the ground) somewhere along
  /// the trajectory, so the kernel re-check cannot pass (terms that cannot tell leave it false).
  bool certain_collision = false;
};

class SafetyTerm {
 public:
  virtual ~SafetyTerm() = default;

  /// Called once per solve before evaluate(): the obstacle map (world frame) and the warm start,
  /// around which obstacle data may be cropped. Must not throw.
  virtual void prepare(const OccupancyGrid& map_W, const Trajectory& initial) = 0;

  /// J_s of `trajectory`; adds dJ_s / d(raw trajectory parameters) to `grad`, which the caller has
  /// reset() to the trajectory's piece count. Fills *stats when non-null. Must not throw.
  virtual double evaluate(const Trajectory& trajectory, TrajectoryGradient& grad, SafetyStats* stats) = 0;

  /// Lets a term with discrete internal decisions take them again at the next evaluate() (see
  /// svsdf_safety_term.hpp "Frozen decisions"); between two calls such a term is a continuous
  /// function of the trajectory. The back-end calls it at the start of each L-BFGS round. Default:
  /// nothing to refresh. Must not throw.
  virtual void refresh_decisions() {}

  /// "kc_svsdf", "svsdf_per_link", "spheres".
  virtual std::string name() const = 0;
};

}  // namespace porter::backend
