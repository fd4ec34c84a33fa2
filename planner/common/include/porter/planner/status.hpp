#pragma once
// The one outcome vocabulary of the planning pipeline: every stage (front-end, mid-end, back-end),
// the acceptance check and the pipeline itself report a Status, printed with to_string() as a
// short, stable token (logs, result files, PLANNER_STATUS). Pure, thread-safe.
//
// Which statuses a stage returns, and which of them come with a result, is stated in the stage's
// header; has_trajectory() answers it for the optimizers (mid-end, back-end).

namespace porter::planner {

enum class Status {
  kSuccess,               ///< the stage did what it was asked (front-end: a path; pipeline: an accepted trajectory)
  kConverged,             ///< optimizer: the relative cost decrease fell below its tolerance
  kConvergedWithWarning,  ///< optimizer: the line search stalled after the cost decreased; last iterate kept
  kIterationLimit,        ///< optimizer: the iteration cap was reached; last iterate kept
  kTimeout,               ///< the time budget ran out (front-end: before a path; optimizers: last iterate kept)
  kCanceled,              ///< the caller's cancellation flag was set (Deadline); nothing usable is returned
  kNoPath,                ///< the search space was exhausted or the goal is provably unreachable
  kInvalidStart,          ///< start outside the map or the joint limits, in collision, or a start state the stage cannot use
  kInvalidGoal,           ///< goal outside the map or the joint limits, or in collision (no valid pose within its tolerance)
  kTrivialPath,           ///< every node of the path coincides: a stationary trajectory is returned
  kInvalidInput,          ///< malformed input (empty path, non-finite values, bad settings)
  kInvalidRobotLimits,    ///< the robot's limits are missing or inconsistent
  kNumericalFailure,      ///< non-finite cost or gradient, or a singular MINCO system
  kOptimizerFailed,       ///< liblbfgs failed without decreasing the cost
  kConstraintViolation,   ///< the optimized trajectory breaks a limit beyond tolerance: not to be executed
  kWarmStartMismatch,     ///< the back-end's warm start does not belong to its problem
  kInCollision,           ///< the acceptance check rejected the trajectory
  kNoMap,                 ///< no map has been set
  kNotRun,                ///< the stage was not needed or not requested
};

/// "success", "converged", "converged_with_warning", "iteration_limit", "timeout", "canceled",
/// "no_path", "invalid_start", "invalid_goal", "trivial_path", "invalid_input",
/// "invalid_robot_limits", "numerical_failure", "optimizer_failed", "constraint_violation",
/// "warm_start_mismatch", "in_collision", "no_map", "not_run".
inline const char* to_string(Status s) {
  switch (s) {
    case Status::kSuccess: return "success";
    case Status::kConverged: return "converged";
    case Status::kConvergedWithWarning: return "converged_with_warning";
    case Status::kIterationLimit: return "iteration_limit";
    case Status::kTimeout: return "timeout";
    case Status::kCanceled: return "canceled";
    case Status::kNoPath: return "no_path";
    case Status::kInvalidStart: return "invalid_start";
    case Status::kInvalidGoal: return "invalid_goal";
    case Status::kTrivialPath: return "trivial_path";
    case Status::kInvalidInput: return "invalid_input";
    case Status::kInvalidRobotLimits: return "invalid_robot_limits";
    case Status::kNumericalFailure: return "numerical_failure";
    case Status::kOptimizerFailed: return "optimizer_failed";
    case Status::kConstraintViolation: return "constraint_violation";
    case Status::kWarmStartMismatch: return "warm_start_mismatch";
    case Status::kInCollision: return "in_collision";
    case Status::kNoMap: return "no_map";
    case Status::kNotRun: return "not_run";
  }
  return "unknown";
}

/// For the optimizers (mid-end, back-end): the statuses that come with a trajectory.
inline bool has_trajectory(Status s) {
  return s == Status::kConverged || s == Status::kConvergedWithWarning || s == Status::kIterationLimit ||
         s == Status::kTimeout || s == Status::kTrivialPath;
}

}  // namespace porter::planner
