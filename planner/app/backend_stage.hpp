#pragma once
// The back-end stage of porter-plan: builds the safety term the flags select (KC-SVSDF, the
// per-link SVSDF ablation or the sphere baseline), runs backend::BackEnd warm started from the
// mid-end's trajectory (the less colliding one when the mid-end was solved twice) and re-checks its
// answer with the kernel trajectory check.

#include <string>
#include <vector>

#include "plan_args.hpp"
#include "porter/backend/backend_result.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::app {

struct BackendRun {
  backend::BackendResult result;
  std::string safety_model;    ///< "kc_svsdf", "svsdf_per_link" or "spheres"
  bool self_collision_term = false;  ///< the self-collision penalty took part
  double setup_s = 0.0;        ///< per-link SDF build (once per robot + payload; not in the budget)
  double budget_s = 0.0;
  /// J_s of each warm start offered (empty when there was one), the one used, and the time the
  /// choice took (part of the budget).
  std::vector<double> warm_start_safety;
  int warm_start = 0;
  double selection_s = 0.0;
};

/// A warm start for the back-end: a mid-end trajectory for the path and the settings it was
/// solved with.
struct BackendWarmStart {
  const Trajectory* trajectory = nullptr;
  midend::MidendSettings settings;
};

/// Runs the back-end on `path` from the warm start with the lowest safety penalty J_s among
/// `warm_starts` (one evaluation of the term each; that time is taken from the budget and reported
/// in BackendRun::selection_s). `recheck` is the kernel checker with the map set. Never throws.
BackendRun run_backend(const PlanArgs& args, const RobotModel& model, const OccupancyGrid& grid_W,
                       const planner::WholeBodyPath& path, const std::vector<BackendWarmStart>& warm_starts,
                       const planner::CollisionChecker& recheck);

}  // namespace porter::app
