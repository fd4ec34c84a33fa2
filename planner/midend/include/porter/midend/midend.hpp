#pragma once
// The MINCO mid-end (paper §V): turns the front-end's discrete whole-body path into a smooth,
// kinematically feasible trajectory that stays near it. Whether it is executed directly is the
// pipeline's acceptance check (planner/pipeline), not the mid-end's.
//
//   MidEnd midend(robot_model);                      // limits come from the robot config
//   MidendResult r = midend.solve(path, planner::Deadline(0.03));
//   if (r.ok() && accepted(*r.trajectory)) publish(*r.trajectory);
//   else if (r.solution) backend.solve(*r.solution, ...);   // the back-end continues from it
//
// solve() never throws and never prints: every outcome is a planner::Status with a message
// (kConverged, kConvergedWithWarning, kIterationLimit, kTimeout and kTrivialPath come with a
// trajectory; kCanceled, kInvalidInput, kInvalidRobotLimits, kNumericalFailure, kOptimizerFailed
// and kConstraintViolation without). Problem construction: midend_problem.hpp; path preparation:
// reference_path.hpp; settings: midend_settings.hpp. Optimizer: the L-BFGS driver
// (lbfgs_driver.hpp), stopping on relative cost decrease (relative_cost_tolerance over
// relative_cost_past iterations), the iteration cap or the deadline (checked after every
// iteration); a run that stops early while still making progress is restarted with a fresh
// memory (max_restarts).
//
// Thread-safety: a MidEnd is immutable after construction; solve() is const and may run
// concurrently from several threads (each call owns its workspace).

#include <optional>

#include "porter/core/robot_model.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_result.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/planner/deadline.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::midend {

class MidEnd {
 public:
  explicit MidEnd(const RobotModel& robot, MidendSettings settings = {});
  explicit MidEnd(const MidendLimits& limits, MidendSettings settings = {});

  const MidendSettings& settings() const { return settings_; }
  const MidendLimits& limits() const { return limits_; }

  /// Optimizes `path` until `deadline` expires (time up: kTimeout with the last iterate;
  /// canceled: kCanceled, no trajectory). The trajectory starts at the path's first node with
  /// `start`'s velocity and acceleration (default: at rest); a start state it cannot use
  /// (non-finite, or moving on a path without motion) is kInvalidStart.
  MidendResult solve(const planner::WholeBodyPath& path, const planner::Deadline& deadline,
                     const StartDerivatives& start = {}) const;
  MidendResult solve(const planner::WholeBodyPath& path, double budget_s) const {
    return solve(path, planner::Deadline(budget_s));
  }

  /// The solution behind `trajectory`, a trajectory this mid-end (same limits and settings) made
  /// for `path` from `start` (e.g. a recorded one): the reference path rebuilt and the decision
  /// vector read back from the pieces (MidendProblem::decision_from_trajectory). nullopt when the
  /// trajectory does not belong to the path.
  std::optional<MidendSolution> solution_for(const planner::WholeBodyPath& path, const Trajectory& trajectory,
                                             const StartDerivatives& start = {}) const;

 private:
  MidendLimits limits_;
  MidendSettings settings_;
};

/// Checks the settings' documented ranges; false with *why naming the first bad field.
bool validate_settings(const MidendSettings& settings, std::string* why);

}  // namespace porter::midend
