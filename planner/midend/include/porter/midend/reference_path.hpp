#pragma once
// The front-end path as the mid-end uses it: cleaned, regrouped into gear segments, densified
// so that every reference edge is short against the residual bounds, and grouped into MINCO
// pieces that each span one or more consecutive reference edges.
//
// From a WholeBodyPath (planner/common/.../whole_body_path.hpp), build_reference_path():
//   1. rejects empty paths, non-finite values and eta not in {+1, -1};
//   2. joins segments: when segment i+1 does not start at segment i's last node it is prefixed
//      with that node (the gear switch happens where the previous segment ended);
//   3. drops consecutive coincident nodes (base position and every joint within
//      coincident_tolerance);
//   4. removes segments whose base path is shorter than min_segment_length_m ("zero-length"
//      segments: the base does not move, so there is no gear switch); their arm motion is kept
//      by appending their nodes to the previous segment (or prepending to the next one);
//   5. merges consecutive segments with the same eta;
//   5a. drops the node next to the goal (start) when it is within 0.1 still_max_base_m,
//      still_max_yaw_rad and still_min_arm_rad of it (a creeping end edge without arm motion);
//   5b. splits off still ends (MidendSettings::still_max_base_m): the longest goal tail of the
//      last segment (start head of the first, unless the base moves at the start) whose base
//      path and heading change are within
//      still_max_base_m / still_max_yaw_rad and which moves the arm by still_min_arm_rad becomes
//      a still segment (base_still, same eta) whose nodes, and the moving part's junction node,
//      carry the goal (start) base pose: the base comes to rest at the goal, then the arm
//      finishes. Skipped when the moving part would no longer move the base;
//   6. splits every edge longer than densify_factor * rho_b (base metric
//      sqrt(|dp|^2 + w_phi dyaw^2)) or densify_factor * rho_m (joints) into equal sub-edges with
//      linearly interpolated nodes (yaw along the shortest arc): the residual's reference nodes;
//   7. allocates initial durations to every edge from a speed profile over all edges: node
//      speeds bounded by the wheel speed on the edge's curvature (v (1 + d_w |kappa| / 2) <=
//      r omega_max), the joint speeds, the start's speed at the global start (0 at rest), 0 at
//      the goal and on still segments, v_ns at gear switches, then forward/backward passes with the wheel acceleration bound (a <= r alpha_max), all at
//      initial_speed_fraction of the limits; an edge lasts 2 L / (v_k + v_k+1), at least its
//      heading / joint motion at the limited rates and min_initial_piece_duration_s; on a still
//      segment the arm edges are timed by per-joint speed profiles (joint speed and acceleration
//      bounds, at the start's joint speeds at the global start, at rest at the goal), so the nodes of an arm motion that ends or
//      starts at rest sit where a braking (accelerating) arm reaches them. The
//      front-end's node times are not used (they are a plan's guess, often a cruise speed far
//      below the limits);
//   8. groups consecutive edges into pieces (greedy along the segment): a piece ends before it
//      would exceed piece_length_m of base path, piece_arm_motion_rad of joint motion or
//      max_edges_per_piece edges; the edge next to a gear switch (not a rest junction) is a piece of its own (the base
//      runs at v_ns there and turns fast; it is sampled gear_sample_factor times denser). A
//      piece's initial duration is the sum of its edges'; each node inside a piece keeps the
//      fraction of the piece's duration at which its edge times put it, so "the node nearest in
//      time" (paper eq. pose_residual) is well defined when the optimizer rescales the piece;
//      the fractions are rounded to multiples of 2 / kappa (see intervals). kappa is at least
//      the initial duration / max_sample_interval_s.
// Why grouping: the front-end drops a node every ~0.25 m and the densification adds one every
// ~0.4 rad of arm motion, so one piece per edge gives 130-260 pieces on the tunnel and forest;
// a quintic easily follows several such edges, and the optimizer's cost per iteration and its
// iteration count both grow with the number of pieces.
// Pure function; thread-safe.

#include <optional>
#include <string>
#include <vector>

#include "porter/core/types.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::midend {

/// The flat output's velocity and acceleration where the trajectory starts, in W (m/s, rad/s,
/// m/s^2, rad/s^2; z = [p_x, p_y, q1..q6]). Zero: the robot starts at rest (the paper's case). A
/// moving base must move along the start heading, in the first segment's driving direction.
struct StartDerivatives {
  TrajVector velocity = TrajVector::Zero();
  TrajVector acceleration = TrajVector::Zero();
  /// The base neither moves nor accelerates (the arm may).
  bool base_at_rest() const { return velocity.head<2>().isZero(0.0) && acceleration.head<2>().isZero(0.0); }
};

struct ReferenceSegment {
  int eta = 1;
  /// A still segment (step 4b): the base rests at its nodes' common base pose (the goal's, or the
  /// start's) while only the arm moves; eta is its moving neighbour's. Its junction with that
  /// neighbour is a rest junction: base velocity and acceleration zero, arm C^2.
  bool base_still = false;
  std::vector<RobotConfiguration> nodes;  ///< >= 2 reference nodes (front-end + densified)
  /// Piece p spans nodes[knots[p]] .. nodes[knots[p + 1]]; knots.front() == 0 and
  /// knots.back() == nodes.size() - 1 (num_pieces() + 1 entries, strictly increasing).
  std::vector<int> knots;
  /// Per node: the fraction of its piece's duration at which the node lies, in (0, 1) for a
  /// node inside a piece and 0 for a knot (a knot is at fraction 1 of the piece it ends); see
  /// fraction_in_piece().
  std::vector<double> node_fraction;
  std::vector<double> durations_s;        ///< initial guess, one per piece
  /// Trapezoid intervals (kappa) of each piece's penalty integrals: max(samples_per_piece,
  /// samples_per_edge * edges, 2 * edges, initial duration / max_sample_interval_s) rounded up to even, times gear_sample_factor next to
  /// a gear switch, at most kMaxSamplesPerPiece. Interior node fractions are multiples of 2 / kappa, so the instant
  /// midway between two nodes, where the nearest node changes, is always a sample.
  std::vector<int> intervals;
  static constexpr int kMaxSamplesPerPiece = 128;
  int num_pieces() const { return static_cast<int>(durations_s.size()); }
  /// Number of reference edges of piece p.
  int edges_in_piece(int p) const { return knots[p + 1] - knots[p]; }
  /// The time fraction of node knots[p] + k inside piece p (k in [0, edges_in_piece(p)]).
  double fraction_in_piece(int p, int k) const {
    return k == edges_in_piece(p) ? 1.0 : node_fraction[knots[p] + k];
  }
};

struct ReferencePath {
  /// Consecutive segments have opposite eta (a gear switch), except next to a still segment
  /// (at most one at each end), which has its moving neighbour's eta (a rest junction).
  std::vector<ReferenceSegment> segments;
  /// The trajectory's velocity and acceleration at the first node (zero: it starts at rest).
  StartDerivatives start;
  /// The same at the last node (zero: it ends at rest).
  StartDerivatives end;
  /// A path cut out of a longer trajectory (the back-end's piece windows, backend/piece_window.hpp)
  /// starts (ends) where that trajectory is, with its velocity and acceleration there (start /
  /// end), while its nodes stay the reference's (the pose residuals' targets). A cut keeps the
  /// min-speed term on the piece next to it, as the longer trajectory's problem does. Empty: the
  /// node, an end of the plan.
  std::optional<TrajVector> cut_start_position;
  std::optional<TrajVector> cut_end_position;
  /// With cut_start_position: the heading there (the trajectory's start heading, which a base at
  /// rest holds; MidendProblem::start_yaw_rad).
  double cut_start_yaw_rad = 0.0;
  /// A cut holds position, velocity and acceleration (the pieces are quintics with those three
  /// at each end), not the jerk: the base's jerk may jump there, and with it the yaw acceleration
  /// and the wheel accelerations. With a weight > 0, the base's jerk (x, y) at a cut is pulled to
  /// the held trajectory's there: cut_jerk_weight |j - j_held|^2, per cut (MidendProblem; counted
  /// in CostBreakdown::cut_jerk, masked with kTermBoundaryHeading).
  std::optional<Eigen::Vector2d> cut_start_base_jerk;
  std::optional<Eigen::Vector2d> cut_end_base_jerk;
  double cut_jerk_weight = 0.0;
  int num_pieces() const {
    int n = 0;
    for (const auto& s : segments) n += s.num_pieces();
    return n;
  }
};

enum class ReferenceOutcome {
  kOk,
  kEmpty,       ///< no node at all
  kMalformed,   ///< non-finite value or bad eta; message says where
  kNoMotion,    ///< every node coincides (path reduces to a single configuration)
};

struct ReferenceBuild {
  ReferenceOutcome outcome = ReferenceOutcome::kEmpty;
  std::string message;
  ReferencePath path;                    ///< valid for kOk
  RobotConfiguration single;             ///< the configuration, for kNoMotion
};

/// `start`: the trajectory's derivatives at the path's first node (zero: at rest).
ReferenceBuild build_reference_path(const planner::WholeBodyPath& path, const MidendLimits& limits,
                                    const MidendSettings& settings, const StartDerivatives& start = {});

}  // namespace porter::midend
