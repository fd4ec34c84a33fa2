#pragma once
// The back-end (paper §VI): when the mid-end's trajectory is not accepted, re-optimize it on the
// mid-end's problem plus the safety penalty J_s of a SafetyTerm (KC-SVSDF by default; and a
// self-collision penalty when the caller gives one, Porter's addition), starting from the mid-end's
// solution (midend::MidendSolution: its reference path, settings and decision vector), within a
// deadline; then re-check the answer with the acceptance test. With an acceptance test, the pieces
// it rejects (each checked on its own) and their neighbours are optimized first with every other
// piece held (piece windows: piece_window.hpp, BackendSettings::window_grow_pieces); the whole
// problem follows only when a window cannot be solved on its own.
//
//   BackEnd backend(robot_model);
//   SvsdfSafetyTerm safety(robot_model, robot_sdf, {});            // or a baseline's term
//   BackendResult r = backend.solve(*mid.solution, map, safety, planner::Deadline(0.3), &acceptance);
//   if (r.success()) publish(*r.trajectory);
//
// solve() never throws and never prints; every outcome is a planner::Status plus a SafetyCheck
// (kConverged, kConvergedWithWarning, kIterationLimit and kTimeout come with a trajectory;
// kCanceled, kInvalidInput, kWarmStartMismatch, kNumericalFailure and kOptimizerFailed without).
// Optimizer: the L-BFGS driver (midend/lbfgs_driver.hpp) with the mid-end's conventions
// (relative-cost stop, iteration cap, deadline checked after every iteration and inside line
// searches; the time in SafetyTerm::prepare counts against the budget).
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
#include "porter/midend/midend_result.hpp"
#include "porter/planner/deadline.hpp"
#include "porter/planner/trajectory_acceptance.hpp"

namespace porter::backend {

class BackEnd {
 public:
  explicit BackEnd(const RobotModel& robot, BackendSettings settings = {});
  BackEnd(const midend::MidendLimits& limits, BackendSettings settings);

  const BackendSettings& settings() const { return settings_; }

  /// `warm_start`: the mid-end's solution (its settings are the problem's); `map_W`: the obstacles;
  /// `acceptance`: the final re-check, also run while optimizing (nullptr: SafetyCheck::kNotChecked
  /// and no in-loop re-checks). `self_collision` (optional, Porter's addition): its J_self joins
  /// J_s (self_collision_term.hpp); prepare()d here from the warm start. Like `safety`, used by one
  /// solve at a time.
  BackendResult solve(const midend::MidendSolution& warm_start, const OccupancyGrid& map_W, SafetyTerm& safety,
                      const planner::Deadline& deadline, const planner::TrajectoryAcceptance* acceptance = nullptr,
                      SelfCollisionTerm* self_collision = nullptr) const;

 private:
  midend::MidendLimits limits_;
  BackendSettings settings_;
};

/// Checks the solver fields' documented ranges; false with *why naming the first bad field.
bool validate_settings(const BackendSettings& settings, std::string* why);

}  // namespace porter::backend
