#pragma once
// What one mid-end solve returns: the status, the trajectory (when there is one), whether it was
// checked collision-free for direct execution, timing, iteration counts and the cost breakdown.
// Plain data.

#include <optional>
#include <string>

#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_status.hpp"

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
  double extra = 0.0;                ///< MidendProblem::set_extra_cost's term (0 without one)

  double total() const {
    return energy + time + wheel_velocity + wheel_acceleration + joint_position + joint_velocity +
           joint_acceleration + residual_base + residual_arm + min_speed + boundary_heading + extra;
  }
  /// Sum of every penalty term (zero means no sampled constraint is violated).
  double penalties() const { return total() - energy - time; }
};

/// What happened after optimization (paper §V "direct execution").
enum class Execution {
  kNotChecked,     ///< no validator was given (or there is no trajectory)
  kDirect,         ///< the validator found it collision-free: execute it, skip the back-end
  kNeedsBackend,   ///< the validator found a collision: hand it to the back-end as a warm start
};

inline const char* to_string(Execution e) {
  switch (e) {
    case Execution::kNotChecked: return "not checked";
    case Execution::kDirect: return "collision-free: direct execution, back-end skipped";
    case Execution::kNeedsBackend: return "in collision: back-end required";
  }
  return "unknown";
}

struct MidendResult {
  MidendStatus status = MidendStatus::kInvalidInput;
  std::string message;                    ///< human-readable detail (liblbfgs code, bad field...)
  std::optional<Trajectory> trajectory;   ///< set iff has_trajectory(status)
  Execution execution = Execution::kNotChecked;

  double elapsed_s = 0.0;                 ///< whole solve() call, validation included
  double optimize_s = 0.0;                ///< L-BFGS alone
  double validate_s = 0.0;                ///< the validator alone
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
