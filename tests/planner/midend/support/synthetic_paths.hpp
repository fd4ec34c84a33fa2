#pragma once
// Synthetic front-end paths for mid-end tests and benchmarks (the real front-end is separate).
// Frozen fixtures: the benchmark numbers are only comparable while these generators are
// unchanged.
//
// Paths are drawn by a "turtle" that drives straight lines and circular arcs forward (eta = +1)
// or in reverse (eta = -1), dropping a node every node_spacing_m of base travel, exactly as a
// Hybrid A* path with Reeds-Shepp-like primitives would, while the arm follows a smooth
// joint-space motion between key poses. Node times assume a cruise speed (front-end time
// allocation).

#include <vector>

#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::midend::testing {

/// Scout Mini + Piper numbers as in config/robots/scout_mini_piper/robot.yaml and its URDF.
RobotModel scout_mini_piper_model();

/// Builds paths primitive by primitive.
class PathBuilder {
 public:
  PathBuilder(BasePose start, JointVector q_start, double node_spacing_m = 0.4,
              double cruise_speed_mps = 0.5);

  /// Drives `length_m` along the heading (eta = +1) or against it (eta = -1).
  PathBuilder& straight(double length_m, int eta);
  /// Drives an arc of `radius_m` turning by `angle_rad` (> 0 left, < 0 right) in direction eta.
  PathBuilder& arc(double radius_m, double angle_rad, int eta);
  /// The arm moves to q_target over the next primitive (linear in base progress, eased).
  PathBuilder& arm_to(const JointVector& q_target);
  /// Adds a node where only the arm moves (base still), at a joint speed of 0.5 rad/s.
  PathBuilder& arm_only(const JointVector& q_target);

  planner::WholeBodyPath build() const { return path_; }

 private:
  void add_node(int eta);
  void primitive(double length_m, double curvature, int eta);

  planner::WholeBodyPath path_;
  BasePose pose_;
  JointVector q_;
  JointVector q_from_, q_to_;
  bool arm_moving_ = false;
  double time_s_ = 0.0;
  double spacing_m_;
  double speed_mps_;
};

JointVector carry_pose();

/// Straight 4 m, a 90-degree left arc of radius 1.2 m, straight 3 m; the arm lifts the payload
/// and swings joint 1 on the way. One forward segment.
planner::WholeBodyPath forward_with_turn();
/// Three-point turn: forward arc left, reverse arc right, forward arc left and a short straight,
/// with arm motions along the way. Three segments (+1, -1, +1).
planner::WholeBodyPath three_point_turn();
/// A ~20 m forest-like slalom (alternating arcs, one reverse manoeuvre) with about
/// `num_nodes` nodes and arm motions: the benchmark's fixture.
planner::WholeBodyPath forest_slalom(int num_nodes = 50);
/// A single forward straight with `num_pieces` + 1 nodes (per-piece cost benchmarks).
planner::WholeBodyPath straight_line(int num_pieces, double spacing_m = 0.4);

}  // namespace porter::midend::testing
