#pragma once
// Private to porter::pipeline: the mid-end stage (solve, acceptance, retry) and the back-end stage
// (warm-start choice, solve) of Planner::plan(). Each fills its report; neither throws.

#include <vector>

#include "porter/backend/backend.hpp"
#include "porter/backend/safety_term.hpp"
#include "porter/backend/self_collision_term.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/midend/midend.hpp"
#include "porter/pipeline/plan_request.hpp"
#include "porter/pipeline/plan_result.hpp"
#include "porter/pipeline/planner_settings.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/deadline.hpp"
#include "porter/planner/trajectory_acceptance.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::pipeline::detail {

/// The mid-end on `path` from `start`, each solve within settings.midend_budget_s (cut short by
/// `cancel`); `acceptance` decides direct execution; `self_checker` finds a self-colliding
/// trajectory, which is always retried (with Stages::kFull any rejected one is).
MidendReport run_midend(const midend::MidEnd& midend, const planner::WholeBodyPath& path, const StartState& start,
                        const PipelineSettings& settings, Stages stages, const planner::TrajectoryAcceptance& acceptance,
                        const planner::CollisionChecker& self_checker, const planner::CancelFlag* cancel);

/// The back-end from the mid-end stage's reported solution, or, with `choose_by_safety` and two
/// solutions, from the one with the lower J_s (the choice counts against the budget); re-checked
/// by `acceptance`.
BackendReport run_backend(const backend::BackEnd& backend, const MidendReport& mid, const OccupancyGrid& map_W,
                          backend::SafetyTerm& safety, backend::SelfCollisionTerm* self_term, double budget_s,
                          bool choose_by_safety,
                          const planner::TrajectoryAcceptance& acceptance, const planner::CancelFlag* cancel);

}  // namespace porter::pipeline::detail
