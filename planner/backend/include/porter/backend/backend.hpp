#pragma once
// The back-end (paper §VI): when the mid-end's trajectory is not collision-free, re-optimize it on
// the mid-end's problem plus the safety penalty J_s of a SafetyTerm (KC-SVSDF by default; and a
// self-collision penalty when the caller gives one, Porter's addition), warm
// started from the mid-end's trajectory, within a time budget; then re-check the answer with the
// kernel motion check.
//
//   BackEnd backend(robot_model);
//   SvsdfSafetyTerm safety(robot_model, robot_sdf, {});            // or a baseline's term
//   BackendResult r = backend.solve(path, *mid.trajectory, map, safety, 0.3, &checker);
//   if (r.success()) publish(*r.trajectory);
//
// solve() never throws and never prints; every outcome is a BackendStatus plus a SafetyCheck.
// Optimizer: liblbfgs with the mid-end's conventions (relative-cost stop, iteration cap, budget
// checked after every iteration; the time in SafetyTerm::prepare counts against the budget).
//
// Thread-safety: a BackEnd is immutable; solve() is const and may run concurrently with separate
// SafetyTerms (each term is used by one solve at a time).

#include "porter/backend/backend_result.hpp"
#include "porter/backend/backend_settings.hpp"
#include "porter/backend/safety_term.hpp"
#include "porter/backend/self_collision_term.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::backend {

class BackEnd {
 public:
  explicit BackEnd(const RobotModel& robot, BackendSettings settings = {});
  BackEnd(const midend::MidendLimits& limits, BackendSettings settings);

  const BackendSettings& settings() const { return settings_; }

  /// `path`: the front-end path the mid-end solved; `warm_start`: the mid-end's trajectory for it
  /// (same MidendSettings as settings().problem); `map_W`: the obstacles; `checker`: the final
  /// re-check (nullptr: SafetyCheck::kNotChecked). time_budget_s <= 0 selects the default.
  /// `self_collision` (optional, Porter's addition): its J_self joins J_s (self_collision_term.hpp);
  /// prepare()d here from the warm start. Like `safety`, used by one solve at a time.
  BackendResult solve(const planner::WholeBodyPath& path, const Trajectory& warm_start,
                      const OccupancyGrid& map_W, SafetyTerm& safety, double time_budget_s,
                      const planner::CollisionChecker* checker = nullptr,
                      SelfCollisionTerm* self_collision = nullptr) const;

 private:
  midend::MidendLimits limits_;
  BackendSettings settings_;
};

/// Checks the solver fields' documented ranges (and the problem's via midend::validate_settings);
/// false with *why naming the first bad field.
bool validate_settings(const BackendSettings& settings, std::string* why);

}  // namespace porter::backend
