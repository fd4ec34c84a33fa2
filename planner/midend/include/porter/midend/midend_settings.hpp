#pragma once
// Parameters of the MINCO mid-end (paper §V). Every field has an in-class default that is the
// value used by the planner daemon unless config overrides it; units are in the names.
// Plain data; copy freely.

#include "porter/minco/penalty.hpp"

namespace porter::midend {

/// liblbfgs line-search choices exposed by the mid-end.
enum class LineSearch { kMoreThuente, kBacktrackingWolfe, kBacktrackingStrongWolfe, kBacktrackingArmijo };

struct MidendSettings {
  // --- Transcription ---------------------------------------------------------------------
  /// kappa: trapezoid intervals per piece for every penalty integral (kappa + 1 samples), at
  /// least; a piece spanning several reference edges gets max(samples_per_piece,
  /// samples_per_edge * edges). Range [2, 64]. REMANI and GCOPTER use 16.
  int samples_per_piece = 16;
  /// Trapezoid intervals per reference edge of a piece (see samples_per_piece). [1, 64].
  int samples_per_edge = 8;
  /// Pieces that touch a gear switch are sampled this many times more densely: near the switch
  /// the base runs at v_ns and its yaw rate/acceleration change fast. [1, 16].
  int gear_sample_factor = 4;
  /// ... and at least initial duration / max_sample_interval_s intervals (0 disables): a long
  /// piece where the base creeps while the arm reconfigures has short bursts of yaw
  /// acceleration at a few cm/s that 32 samples over 3.6 s step over (forest seed 20: wheel
  /// acceleration 1.35 x the limit for 0.2 s between samples, penalty ~0; 0.05-0.08 all fix
  /// it). s, >= 0.
  double max_sample_interval_s = 0.06;

  // --- Objective: control effort and time -------------------------------------------------
  /// Diagonal of W for p_x, p_y (weights the squared base jerk, s^5/m^2 per unit cost). > 0.
  double energy_weight_base = 1.0;
  /// Diagonal of W for q1..q6 (weights the squared joint jerk). > 0.
  double energy_weight_joint = 1.0;
  /// rho_T: cost per second of total duration. > 0; larger trades smoothness for speed.
  /// With 20 no limit bound at the optimum on the scene paths (forest seed 2: 97 s for 23 m,
  /// base <= 0.53 m/s of 1.05, joints <= 0.65 of their speed limit; the jerk energy E and
  /// rho_T T balance at 5 E ~ rho_T T); with 100 the wheel and joint limits bind and the
  /// trajectories are 10-20 % shorter (scripts/bench-midend).
  double time_weight_per_s = 100.0;

  // --- Penalties (constraint transcription) -----------------------------------------------
  /// Shape of the one-sided penalty applied to every normalized violation x (x <= 0 is
  /// feasible). Wheel, joint-rate and residual constraints are normalized to be dimensionless
  /// (e.g. omega^2 / omega_max^2 - 1); joint positions are in rad.
  minco::PenaltyKind penalty_kind = minco::PenaltyKind::kSmoothedL1;
  /// mu of the smoothed L1, in units of the normalized violation. (0, 1].
  double penalty_smoothing = 1e-2;
  /// Weights (cost per second of violation at unit normalized violation). >= 0; 0 disables.
  double weight_wheel_velocity = 2e4;       ///< |omega_l|, |omega_r| <= wheel_omega_max
  double weight_wheel_acceleration = 2e4;   ///< |alpha_l|, |alpha_r| <= wheel_alpha_max
  double weight_joint_position = 2e4;       ///< lower <= q <= upper
  double weight_joint_velocity = 2e4;       ///< |q_dot| <= velocity_max
  double weight_joint_acceleration = 2e4;   ///< |q_ddot| <= acceleration_max
  /// The wheel omega / alpha and joint q_dot / q_ddot penalties start at this fraction of their
  /// limits (|omega| beyond f omega_max, ...); the limits themselves, and the result check, stay
  /// the limits. Why: the penalty is soft, and at its optimum a binding limit sits a little
  /// beyond the point where the penalty starts (tunnel seed 7 with f = 1: wheel acceleration
  /// 1.023 x the limit at 1 ms, at 0.06 m/s where the yaw acceleration dominates). (0, 1].
  double limit_penalty_fraction = 0.98;
  /// e_b (paper eq. pose_residual) <= 0, e_m <= 0: five times the limits' weight. A sample's
  /// weight is proportional to its piece's duration / kappa, and on short, fast pieces (the arm
  /// finishing at the goal) 2e4 let the optimum sit 3-5 % beyond rho_m (forest seeds 15, 18, 20).
  double weight_residual_base = 1e5;
  double weight_residual_arm = 1e5;
  /// Keeps |p_xy'| >= min_speed_fraction * v_ns inside every segment (not on the pieces that
  /// leave the global start or reach the goal, which are at rest, nor on pieces whose
  /// reference edge does not move the base), so the yaw atan2(eta v) and the wheel rates stay
  /// defined and bounded (REMANI's non-singular speed). Normalized as 1 - |v|^2 / v_min^2.
  double weight_min_speed = 2e4;
  double min_speed_fraction = 1.0;
  /// ... but on a piece the kept speed is at most this fraction of the reference's own mean
  /// speed over it (base path / initial duration), so a piece where the front-end creeps (a long
  /// arm motion over millimetres of base path) is not pushed past its nodes. (0, 1].
  double slow_reference_fraction = 0.5;
  /// Weight of the rest-boundary heading term: at the global start and goal the base is at
  /// rest, so its direction of motion is the jerk's; this aligns eta * jerk with the node's
  /// yaw (cost about weight * |angle|, rounded within 2 mrad of alignment, gated to vanish when
  /// the base does not move: midend_problem.cpp). >= 0. A cost quadratic in the angle let the
  /// time term (time_weight_per_s = 100) hold the start or goal heading 0.06-0.07 rad off.
  double weight_boundary_heading = 5e4;

  // --- Pose residuals to the front-end path -----------------------------------------------
  /// rho_b: bound on sqrt(|p - p_k|^2 + w_phi * angle(phi, phi_k)^2), m. > 0.
  double residual_base_bound_m = 0.35;
  /// rho_m: bound on |q - q_k| (Euclidean over the 6 joints), rad. > 0.
  double residual_arm_bound_rad = 0.35;
  /// w_phi: m^2 per rad^2 in the base residual. >= 0.
  double residual_yaw_weight_m2 = 0.1;
  /// The residual penalties start at this fraction of rho_b / rho_m (e_b is penalised beyond
  /// (f rho_b)^2, e_m beyond (f rho_m)^2); the bounds themselves stay rho_b, rho_m. Why: the
  /// constraint holds for every t (paper eq. pose_residual) and is largest just before the
  /// instant where the nearest node changes, but the penalty is a soft, sampled integral: at
  /// its optimum the samples there sit a few percent beyond the point where the penalty starts
  /// (measured on forest paths with f = 1: up to 5 % of rho_m over, at the sample itself). With
  /// 0.97 and the residual weights below, 18 of 18 re-solved forest paths keep the residuals
  /// within rho at 1 ms (1 % slack); 0.95 passes as well but takes ~15 % more evaluations. (0, 1].
  double residual_penalty_fraction = 0.97;

  // --- Singularity guards (see diff_drive.hpp) --------------------------------------------
  /// epsilon in |v|^2 + epsilon^2 wherever the base speed divides (yaw rate, wheel rates).
  /// Only speeds below ~epsilon are affected. > 0.
  double speed_guard_mps = 1e-3;
  /// The yaw part of e_b is multiplied by |v|^2 / (|v|^2 + gate^2): yaw is undefined at rest.
  double yaw_gate_speed_mps = 2e-2;
  /// The boundary heading term is gated the same way on |jerk|, m/s^3.
  double boundary_jerk_guard_mps3 = 1e-2;

  // --- Reference path preparation ----------------------------------------------------------
  /// Consecutive nodes closer than this in base position (m) and every joint (rad) are merged.
  double coincident_tolerance = 1e-6;
  /// A segment whose base path is shorter than this (m) carries no base motion: its arm motion
  /// is merged into a neighbour and its gear switches are dropped.
  double min_segment_length_m = 1e-3;
  /// Still ends (reference_path.hpp, step 5b). The front-end often reaches the goal with a last
  /// edge that moves the base a few millimetres while the arm turns by a radian (and may leave
  /// the start likewise). Timed by the arm, such an edge asks the base to creep, and a quintic
  /// entering it at speed overshoots and reverses inside the segment. Instead, a goal tail (start
  /// head) of front-end edges of the end segment whose base path is at most still_max_base_m,
  /// whose heading changes by at most still_max_yaw_rad and which moves the arm by at least
  /// still_min_arm_rad (Euclidean over the joints) becomes a still segment: the base rests at
  /// the goal (start) pose while the arm finishes (starts) its motion. still_max_base_m = 0
  /// disables. Keep still_max_base_m well below residual_base_bound_m: the still segment's nodes
  /// are moved onto the end pose. >= 0, >= 0, >= 0.
  double still_max_base_m = 0.1;
  double still_max_yaw_rad = 0.25;
  double still_min_arm_rad = 0.05;
  /// Edges longer than densify_factor * rho (base metric or joints) are split into pieces
  /// with linearly interpolated reference nodes, so the nearest node stays within reach. >= 1.
  /// The residual uses the node nearest in *time*; on a rest-to-rest piece the position at half
  /// the piece's duration is ~0.8 of the edge away from the start node, so edges must stay
  /// below ~1.2 rho for the residual to be satisfiable at all.
  double densify_factor = 1.2;
  /// Upper bound on reference edges inserted per front-end edge by densification. >= 1.
  int max_pieces_per_edge = 16;
  /// Grouping of reference edges into MINCO pieces (reference_path.hpp, step 8): a piece spans
  /// at most this much base path (m), joint motion (Euclidean over the 6 joints, rad) and this
  /// many edges. 1 edge per piece reproduces one piece per reference edge. > 0, >= 1.
  double piece_length_m = 1.0;
  double piece_arm_motion_rad = 1.0;
  int max_edges_per_piece = 4;
  /// Edges whose initial durations differ by more than this factor from the piece's first edge
  /// start a new piece (acceleration zones keep their waypoints). >= 1.
  double piece_duration_ratio = 1.5;
  /// Initial durations (reference_path.hpp, step 7): a speed profile along the base path at this
  /// fraction of the wheel speed / wheel acceleration / joint speed limits (rest at the goal and
  /// start, v_ns at gear switches). (0, 1]. 0.85 starts close to the optimum's duration (on
  /// forest_slalom(50): 24.2 s initial, 22.0 s optimized; 0.5 starts at 40.9 s).
  double initial_speed_fraction = 0.85;
  /// Floor on initial piece durations, s. > 0.
  double min_initial_piece_duration_s = 0.1;

  // --- Solver (liblbfgs) ----------------------------------------------------------------------
  int max_iterations = 1000;                ///< iteration cap; >= 1
  /// Stop when (f_{k-past} - f_k) / f_k < relative_cost_tolerance. > 0. 1e-3 over 3 iterations
  /// (measured on forest_slalom(50): 228 evaluations, total duration 22.0 s) instead of 1e-4
  /// (1292 evaluations, 20.8 s): the tail of the run is a slow crawl along the penalty valley.
  double relative_cost_tolerance = 1e-3;
  /// Iterations over which the decrease is measured. 2 saves ~30 % of the evaluations but
  /// stopped forest seeds 4 and 16 with a joint 2.2 % of its range out and the arm residual at
  /// 1.031 rho_m (measured); 3 passes them.
  int relative_cost_past = 3;
  int memory_size = 32;                     ///< L-BFGS corrections kept; [3, 64]
  int max_line_search = 40;                 ///< evaluations per line search
  /// L-BFGS runs on x / variable_scale. Its iterations are invariant to this scale except the
  /// first, whose trial step moves x by exactly variable_scale (liblbfgs starts with
  /// step = 1 / |gradient|); 1e-3 is about the first acceptable step on these costs, which
  /// saves the ~10 halvings a unit first step needs. > 0.
  double variable_scale = 1e-3;
  /// L-BFGS restarts (fresh curvature memory) after a run that stopped on the relative-decrease
  /// test or a stalled line search but still lowered the cost by more than
  /// restart_min_decrease * cost. >= 0.
  int max_restarts = 2;
  double restart_min_decrease = 1e-3;
  /// Backtracking with the regular Wolfe condition: on these stiff penalized costs liblbfgs'
  /// More-Thuente search stops early with LBFGSERR_ROUNDING_ERROR far from the optimum (measured
  /// on the synthetic paths: total duration 30-50 % longer). Near gear switches and rest
  /// boundaries the wheel-acceleration penalty (yaw acceleration at |v| <= v_ns) makes full
  /// quasi-Newton steps overshoot by orders of magnitude, hence ~2 evaluations per iteration.
  LineSearch line_search = LineSearch::kBacktrackingWolfe;
  /// Result check (planner::Status::kConstraintViolation): the final trajectory is sampled every
  /// verify_step_s through porter::Trajectory; a wheel or joint limit exceeded by more than
  /// verify_tolerance (relative; joint positions: fraction of the range) or a base reversal
  /// inside a segment rejects it. The penalties leave small violations between samples, hence
  /// the tolerance. verify_step_s <= 0 disables the check. tolerance >= 0.
  double verify_tolerance = 0.05;
  double verify_step_s = 0.01;
};

}  // namespace porter::midend
