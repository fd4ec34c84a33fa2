#pragma once
// The planning pipeline (paper §IV-§VI) as one object, built once per robot + payload + settings
// and kept for many plans and maps: the CLI, the planner daemon, the benchmarks and the tests all
// plan through it.
//
//   Planner planner(model_with_payload, settings);      // robot side: kernels, proofs (~0.3 s)
//   planner.set_map(grid_W);                             // map side: full or incremental update
//   PlanResult r = planner.plan(request);                // goal -> front -> mid -> back -> accept
//   if (r.success()) publish(*r.trajectory);
//
// plan():
//   1. goal: the request's GoalSpec becomes a goal configuration (goal.hpp in src/: the exact
//      pose and arm when valid; a free arm chosen, the start's first; an invalid pose moved
//      within its tolerance); the start is checked the same way;
//   2. front-end (frontend.hpp) within its budget;
//   3. mid-end (midend.hpp) from the start state, within its budget; the acceptance test decides
//      whether its trajectory is executed directly. A rejected trajectory is solved again with a
//      tighter arm residual (PipelineSettings::retry_arm_residual_scale);
//   4. back-end (backend.hpp) from the mid-end's solution when the mid-end's trajectory was
//      rejected (Stages::kFull), warm started from the better of the two solves; its answer is
//      accepted or not by the same test.
// Each stage reports its status, times and iterations (PlanResult, time_breakdown()).
//
// Kept across plans and maps (robot + payload only; built in the constructor, or on the first
// plan that needs them): the kernel robot side (planner/collision kernel_robot.hpp), the per-link
// SDFs (backend/robot_sdf.hpp) and the back-end's terms. set_map() replaces only the map side:
// the kernel map (incremental when the grid keeps its geometry), the front-end's heuristic grid,
// the sphere baseline's distance field; the back-end's obstacle points follow on its next solve.
//
// Failure: the constructor throws std::invalid_argument for invalid settings (load time);
// set_map() and plan() never throw and report through their results.
// Thread-safety: one thread plans and sets maps (plan() and set_map() need exclusive access);
// another may set the request's CancelFlag at any time. Not copyable or movable (the stages refer
// to its members).

#include <memory>
#include <optional>
#include <string>

#include "porter/backend/robot_sdf.hpp"
#include "porter/backend/safety_term.hpp"
#include "porter/backend/self_collision_term.hpp"
#include "porter/backend/backend.hpp"
#include "porter/baselines/sphere_collision_checker.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/midend/midend.hpp"
#include "porter/pipeline/kernel_acceptance.hpp"
#include "porter/pipeline/plan_request.hpp"
#include "porter/pipeline/plan_result.hpp"
#include "porter/pipeline/planner_settings.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"
#include "porter/planner/trajectory_acceptance.hpp"

namespace porter::pipeline {

/// What set_map() did.
struct MapUpdate {
  bool ok = false;
  std::string message;         ///< why the map was refused ("" when ok)
  bool incremental = false;    ///< the kernel map was updated in place (same grid geometry)
  std::int64_t changed_voxels = 0;
  double time_s = 0.0;
};

/// Robot-side builds so far.
struct SetupReport {
  double kernels_s = 0.0;  ///< kernel robot side (constructor)
  double backend_s = 0.0;  ///< per-link SDFs and the back-end's terms (0 until built)
  bool backend_ready = false;
  /// The acceptance test's clearance margin the back-end's terms were built for, m (negative: the
  /// kernel check's inflation).
  double safety_margin_m = -1.0;
};

class Planner {
 public:
  /// `model`: the robot with its payload attached (copied). Builds the robot side. Throws
  /// std::invalid_argument when validate_settings() fails or the kernels cannot be built.
  Planner(RobotModel model, PlannerSettings settings);
  Planner(const Planner&) = delete;
  Planner& operator=(const Planner&) = delete;

  /// Adopts an obstacle map (occupancy in W at the kernels' resolution). A grid with the same
  /// origin, resolution and size as the current one updates the kernel map incrementally.
  MapUpdate set_map(const OccupancyGrid& map_W);
  bool has_map() const { return has_map_; }

  PlanResult plan(const PlanRequest& request);

  /// Builds the back-end's robot side now instead of on the first plan that needs it. Throws
  /// std::invalid_argument when a term refuses its settings (plan() reports that as
  /// kInvalidInput instead).
  void prepare_backend();

  /// Replaces the acceptance test (nullptr: back to the kernel trajectory check). Must outlive
  /// the Planner's use of it. A test that states a clearance margin (e.g. ExactClearanceAcceptance)
  /// also sets the back-end's safety margins (rebuilt on the next plan that needs them).
  void set_acceptance(std::shared_ptr<const planner::TrajectoryAcceptance> acceptance);
  const planner::TrajectoryAcceptance& acceptance() const { return *acceptance_; }

  const RobotModel& model() const { return model_; }
  const PlannerSettings& settings() const { return settings_; }
  const SetupReport& setup() const { return setup_; }
  /// The kernel checker (map set by set_map()): the acceptance test's and, with kKernels, the
  /// front-end's.
  const planner::KernelCollisionChecker& kernel_checker() const { return *kernels_; }
  /// The front-end's checker (the kernels, or the sphere baseline).
  const planner::CollisionChecker& frontend_checker() const;

 private:
  friend class PlanRun;

  const RobotModel model_;
  const PlannerSettings settings_;
  SetupReport setup_;
  std::shared_ptr<const planner::KernelRobot> kernel_robot_;
  std::unique_ptr<planner::KernelCollisionChecker> kernels_;
  std::unique_ptr<baselines::SphereCollisionChecker> spheres_;
  std::shared_ptr<const planner::TrajectoryAcceptance> acceptance_;
  std::unique_ptr<frontend::FrontEnd> frontend_;
  midend::MidEnd midend_;
  backend::BackEnd backend_;
  // Built by prepare_backend().
  std::optional<backend::RobotSdf> sdf_;
  std::unique_ptr<backend::SafetyTerm> safety_term_;
  std::unique_ptr<backend::SelfCollisionTerm> self_term_;
  OccupancyGrid map_W_;
  bool has_map_ = false;
};

}  // namespace porter::pipeline
