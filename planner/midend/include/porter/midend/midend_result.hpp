#pragma once
// What one mid-end solve returns: the status, the trajectory and the solution behind it (when
// there is one), timing, iteration counts and the cost breakdown. Plain data.

#include <optional>
#include <string>

#include <Eigen/Core>

#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/midend/reference_path.hpp"
#include "porter/planner/status.hpp"

namespace porter::midend {

/// The mid-end objective split by term (each already multiplied by its weight).
struct CostBreakdown {
  double energy = 0.0;               ///< int psi^T W psi dt
  double time = 0.0;                 ///< rho_T * T_total
  double wheel_velocity = 0.0;
  double wheel_acceleration = 0.0;
  double joint_position = 0.0;
  double joint_velocity = 0.0;
  double joint_acceleration = 0.0;
  double residual_base = 0.0;        ///< e_b penalty
  double residual_arm = 0.0;         ///< e_m penalty
  double min_speed = 0.0;            ///< non-singular speed inside segments
  double boundary_heading = 0.0;
  double cut_jerk = 0.0;             ///< ReferencePath::cut_jerk_weight's term (0 without cuts)
  double extra = 0.0;                ///< MidendProblem::set_extra_cost's term (0 without one)

  double total() const {
    return energy + time + wheel_velocity + wheel_acceleration + joint_position + joint_velocity +
           joint_acceleration + residual_base + residual_arm + min_speed + boundary_heading + cut_jerk + extra;
  }
  /// Sum of every penalty term (zero means no sampled constraint is violated).
  double penalties() const { return total() - energy - time; }
};

/// The mid-end's solution as a value the back-end continues from: the prepared reference path
/// (its start state included), the settings it was solved with and the decision vector in the
/// layout of midend_problem.hpp. MidendProblem(reference, limits, settings) evaluated at x gives
/// the returned trajectory; the back-end adds its safety term to that same problem and starts
/// at x.
struct MidendSolution {
  ReferencePath reference;
  MidendSettings settings;
  Eigen::VectorXd x;
};

struct MidendResult {
  planner::Status status = planner::Status::kInvalidInput;
  std::string message;                    ///< human-readable detail (liblbfgs code, bad field...)
  std::optional<Trajectory> trajectory;   ///< set iff has_trajectory(status)
  /// Set with the trajectory of an optimized problem (not for kTrivialPath).
  std::optional<MidendSolution> solution;

  double elapsed_s = 0.0;                 ///< whole solve() call
  double prepare_s = 0.0;                 ///< reference path, problem and initial guess (part of elapsed_s)
  double optimize_s = 0.0;                ///< L-BFGS alone (part of elapsed_s); the rest is the result check
  int iterations = 0;                     ///< L-BFGS iterations
  int evaluations = 0;                    ///< cost + gradient evaluations
  int lbfgs_code = 0;                     ///< raw lbfgs() return code
  int num_pieces = 0;
  int num_segments = 0;
  int num_variables = 0;

  CostBreakdown initial_cost;             ///< at the initial guess
  CostBreakdown final_cost;               ///< at the returned trajectory

  bool ok() const { return has_trajectory(status) && trajectory.has_value(); }
};

}  // namespace porter::midend
