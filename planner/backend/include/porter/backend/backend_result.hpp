#pragma once
// What one back-end solve returns: the optimizer's status, the trajectory when there is one, the
// final collision re-check, timing, iteration counts and the cost split. Plain data.

#include <optional>
#include <string>

#include "porter/backend/backend_problem.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/planner/status.hpp"

namespace porter::backend {

/// The final re-check by the acceptance test (planner/trajectory_acceptance.hpp).
enum class SafetyCheck { kNotChecked, kCollisionFree, kInCollision };

inline const char* to_string(SafetyCheck c) {
  switch (c) {
    case SafetyCheck::kNotChecked: return "not checked";
    case SafetyCheck::kCollisionFree: return "collision-free";
    case SafetyCheck::kInCollision: return "in collision";
  }
  return "unknown";
}

struct BackendResult {
  planner::Status status = planner::Status::kInvalidInput;
  std::string message;
  std::optional<Trajectory> trajectory;
  SafetyCheck check = SafetyCheck::kNotChecked;
  int collision_link = -1;          ///< first link the re-check found in collision
  std::string safety_term;          ///< SafetyTerm::name()

  double elapsed_s = 0.0;           ///< whole solve(), re-check included
  double prepare_s = 0.0;           ///< problem, warm start and SafetyTerm::prepare (part of elapsed_s)
  double optimize_s = 0.0;          ///< L-BFGS
  double safety_s = 0.0;            ///< inside SafetyTerm::evaluate (part of optimize_s)
  double safety_prefilter_s = 0.0;  ///< of which the term's prefilter (SafetyStats::prefilter_s)
  double self_collision_s = 0.0;    ///< inside SelfCollisionTerm::evaluate (part of optimize_s)
  double check_s = 0.0;             ///< the re-check
  double recheck_s = 0.0;           ///< in-loop re-checks (part of optimize_s)
  int iterations = 0;               ///< over every round
  int evaluations = 0;
  int rechecks = 0;                 ///< in-loop kernel re-checks (BackendSettings)
  int probe_evaluations = 0;        ///< first-step probes (BackendSettings::probe_first_step)
  int safety_skips = 0;             ///< evaluations that skipped J_s (skip_safety_above_current)
  int rounds = 1;                   ///< L-BFGS rounds (1 + safety-weight escalations)
  double safety_weight_scale = 1.0; ///< of the last round
  int lbfgs_code = 0;
  // Piece windows (BackendSettings::window_grow_pieces; all zero / false without them):
  double window_localise_s = 0.0;   ///< checking each piece of the warm start on its own (part of elapsed_s)
  int window_flagged = 0;           ///< warm-start pieces the acceptance test rejected on their own
  int window_solves = 0;            ///< window problems solved (a grown window counts again)
  int window_pieces = 0;            ///< pieces over those solves
  bool window_fallback = false;     ///< the whole problem was solved after the windows
  int num_pieces = 0;
  int num_variables = 0;

  /// At the warm start and at the returned trajectory. With piece windows: the initial cost is
  /// the first window problem's (its pieces only), the final cost the last window problem's, or
  /// the whole problem's when it followed the windows.
  BackendCost initial_cost;
  BackendCost final_cost;

  bool ok() const { return has_trajectory(status) && trajectory.has_value(); }
  /// A trajectory that passed the re-check.
  bool success() const { return ok() && check == SafetyCheck::kCollisionFree; }
};

}  // namespace porter::backend
