#pragma once
// What Planner::plan() returns: the pipeline's status, each stage's report (status, times,
// iterations), the final acceptance test and the trajectory, plus where the time went. Plain data.
//
// Status (porter/planner/status.hpp) of the whole plan:
//   kSuccess        every requested stage succeeded: with Stages::kFront a path, otherwise a
//                   trajectory the acceptance test accepted;
//   kInCollision    a trajectory was produced but not accepted (with Stages::kMid: the mid-end's;
//                   kFull: the back-end's, or the mid-end's when the back-end could not run);
//   kInvalidStart / kInvalidGoal   the start (or its state) / the goal cannot be used;
//   kNoMap          set_map() was not called;
//   kCanceled       the request's cancellation flag was set;
//   otherwise the failing stage's status (front-end kTimeout / kNoPath, a mid-end or back-end
//   failure without a trajectory).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "porter/backend/backend_result.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/midend/midend_result.hpp"
#include "porter/planner/status.hpp"
#include "porter/planner/trajectory_acceptance.hpp"

namespace porter::pipeline {

/// The goal actually planned for (GoalSpec resolved).
struct GoalReport {
  planner::Status status = planner::Status::kNotRun;  ///< kSuccess, kInvalidGoal, kInvalidStart
  std::string message;
  RobotConfiguration config;     ///< the goal configuration given to the front-end
  bool base_moved = false;       ///< the exact base pose was invalid: a pose within the tolerance
  bool arm_chosen = false;       ///< the arm was free and the planner chose it
  int candidates = 0;            ///< goal configurations checked
  double time_s = 0.0;
};

/// The mid-end stage: one solve, or two with the retry (PipelineSettings::retry_arm_residual_scale).
struct MidendReport {
  /// The reported solve; with a retry its time, iterations and evaluations are summed over both.
  midend::MidendResult result;
  /// The first solve when the retry replaced it and both were rejected: the back-end's second
  /// warm start.
  std::optional<midend::MidendResult> first;
  std::string retry;                          ///< why the mid-end was solved again ("" if not)
  double residual_arm_bound_rad = 0.0;        ///< rho_m of the reported solve
  planner::AcceptanceResult acceptance;       ///< of the reported solve's trajectory
  double acceptance_s = 0.0;                  ///< acceptance tests of the stage (both solves)
  double self_check_s = 0.0;                  ///< the self-collision test that decides the retry
  double time_s = 0.0;                        ///< the whole stage
};

/// The back-end stage.
struct BackendReport {
  backend::BackendResult result;
  std::string safety_model;           ///< "kc_svsdf", "svsdf_per_link" or "spheres"
  bool self_collision_term = false;   ///< the self-collision penalty took part
  double budget_s = 0.0;
  /// Robot-side builds this plan needed (per-link SDFs, the terms' robot data): once per Planner,
  /// not in the budget; 0 on later plans.
  double setup_s = 0.0;
  /// J_s of each warm start offered (empty with one), the one used (0: the reported mid-end
  /// solve, 1: the first solve), and the time the choice took (part of the budget).
  std::vector<double> warm_start_safety;
  int warm_start = 0;
  double selection_s = 0.0;
};

/// The acceptance test of the answer.
struct FinalCheck {
  std::string stage;    ///< whose trajectory: "midend" or "backend"
  std::string checker;  ///< TrajectoryAcceptance::name()
  planner::AcceptanceResult result;
  double time_s = 0.0;
};

struct PlanResult {
  planner::Status status = planner::Status::kNotRun;
  std::string message;  ///< why it failed ("" on success)
  GoalReport goal;
  std::optional<frontend::FrontendResult> frontend;
  std::optional<MidendReport> midend;
  std::optional<BackendReport> backend;
  std::optional<FinalCheck> final_check;
  /// The answer: the back-end's trajectory when it returned one, else the mid-end's (also when
  /// it was not accepted: status says so).
  std::optional<Trajectory> trajectory;
  double total_s = 0.0;  ///< the whole plan() call
  double setup_s = 0.0;  ///< robot-side builds inside this call (first plans only)

  bool success() const { return status == planner::Status::kSuccess; }
  /// Where the time went, in pipeline order: ("goal", s), ("frontend.hybrid_astar", s), ...,
  /// ("midend.prepare", s), ("midend.optimize", s), ("midend.acceptance", s), ...,
  /// ("backend.setup", s), ("backend.optimize", s), ("backend.safety_term", s), ...
  /// Nested names are parts of their parent ("backend.safety_term" is inside
  /// "backend.optimize").
  std::vector<std::pair<std::string, double>> time_breakdown() const;
};

}  // namespace porter::pipeline
