#pragma once
// The MINCO mid-end (paper §V): turns the front-end's discrete whole-body path into a smooth,
// kinematically feasible trajectory that stays near it, then optionally checks it for direct
// execution.
//
//   MidEnd midend(robot_model);                      // limits come from the robot config
//   MidendResult r = midend.solve(path, 0.03, validator);
//   if (r.ok() && r.execution == Execution::kDirect) publish(*r.trajectory);
//   else if (r.ok()) backend.solve(*r.trajectory, ...);
//
// solve() never throws and never prints: every outcome is a MidendStatus with a message.
// Problem construction: midend_problem.hpp; path preparation: reference_path.hpp; settings:
// midend_settings.hpp. Optimizer: liblbfgs, stopping on relative cost decrease
// (relative_cost_tolerance over relative_cost_past iterations), the iteration cap or the time
// budget (checked after every iteration through the progress callback); a run that stops early
// while still making progress is restarted with a fresh memory (max_restarts).
//
// Thread-safety: a MidEnd is immutable after construction; solve() is const and may run
// concurrently from several threads (each call owns its workspace). The validator is called on
// the solving thread.

#include <functional>

#include "porter/core/robot_model.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_result.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::midend {

/// Direct-execution hook: returns true when the trajectory is collision-free (the kernel
/// motion check along it). Must not throw.
using TrajectoryValidator = std::function<bool(const Trajectory&)>;

class MidEnd {
 public:
  explicit MidEnd(const RobotModel& robot, MidendSettings settings = {});
  explicit MidEnd(const MidendLimits& limits, MidendSettings settings = {});

  const MidendSettings& settings() const { return settings_; }
  const MidendLimits& limits() const { return limits_; }

  /// Optimizes `path` within time_budget_s (<= 0: settings().default_time_budget_s); the
  /// budget covers the optimization, not the validator. When the result has a trajectory and
  /// `validator` is set, it is called once and result.execution records the decision.
  MidendResult solve(const planner::WholeBodyPath& path, double time_budget_s,
                     const TrajectoryValidator& validator = {}) const;

 private:
  MidendLimits limits_;
  MidendSettings settings_;
};

/// Checks the settings' documented ranges; false with *why naming the first bad field.
bool validate_settings(const MidendSettings& settings, std::string* why);

}  // namespace porter::midend
