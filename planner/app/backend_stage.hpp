#pragma once
// The back-end stage of porter-plan: builds the safety term the flags select (KC-SVSDF, the
// per-link SVSDF ablation or the sphere baseline), runs backend::BackEnd warm started from the
// mid-end's trajectory and re-checks its answer with the kernel trajectory check.

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
};

/// Runs the back-end on `path` from `warm_start` (the mid-end's trajectory for it, solved with
/// `midend_settings`). `recheck` is the kernel checker with the map set. Never throws.
BackendRun run_backend(const PlanArgs& args, const RobotModel& model, const OccupancyGrid& grid_W,
                       const planner::WholeBodyPath& path, const Trajectory& warm_start,
                       const midend::MidendSettings& midend_settings, const planner::CollisionChecker& recheck);

}  // namespace porter::app
