#pragma once
// Outcome of one mid-end solve (OMPL PlannerStatus style). Pure, thread-safe.

namespace porter::midend {

enum class MidendStatus {
  /// Relative cost decrease fell below the tolerance (or the gradient vanished).
  kConverged,
  /// The line search could not make progress (liblbfgs rounding/line-search limits) after the
  /// cost had decreased from the initial guess; the last accepted iterate is returned.
  kConvergedWithWarning,
  /// The iteration cap was reached; the last iterate is returned.
  kIterationLimit,
  /// The time budget ran out; the last accepted iterate is returned.
  kTimeBudgetExceeded,
  /// Every node of the path coincides: a stationary one-piece trajectory is returned.
  kTrivialPath,
  /// The path is empty or malformed (non-finite values, eta not +-1); no trajectory.
  kInvalidInput,
  /// The robot limits are missing or inconsistent; no trajectory.
  kInvalidRobotLimits,
  /// The cost or gradient became non-finite or the MINCO system was singular; no trajectory.
  kNumericalFailure,
  /// liblbfgs failed without decreasing the cost (or with an internal error); no trajectory.
  kOptimizerFailed,
  /// The optimized trajectory breaks a limit by more than MidendSettings::verify_tolerance or
  /// the base reverses inside a segment (a poor local minimum, typically on a degenerate path);
  /// the message says what and when. No trajectory: it must not be executed.
  kConstraintViolation,
};

inline const char* to_string(MidendStatus s) {
  switch (s) {
    case MidendStatus::kConverged: return "converged";
    case MidendStatus::kConvergedWithWarning: return "converged with warning (line search stalled after cost decrease)";
    case MidendStatus::kIterationLimit: return "iteration limit reached";
    case MidendStatus::kTimeBudgetExceeded: return "time budget exceeded";
    case MidendStatus::kTrivialPath: return "trivial path (no motion)";
    case MidendStatus::kInvalidInput: return "invalid input path";
    case MidendStatus::kInvalidRobotLimits: return "invalid robot limits";
    case MidendStatus::kNumericalFailure: return "numerical failure";
    case MidendStatus::kOptimizerFailed: return "optimizer failed";
    case MidendStatus::kConstraintViolation: return "constraint violation in the optimized trajectory";
  }
  return "unknown";
}

/// True for the statuses that come with a trajectory.
inline bool has_trajectory(MidendStatus s) {
  return s == MidendStatus::kConverged || s == MidendStatus::kConvergedWithWarning ||
         s == MidendStatus::kIterationLimit || s == MidendStatus::kTimeBudgetExceeded ||
         s == MidendStatus::kTrivialPath;
}

}  // namespace porter::midend
