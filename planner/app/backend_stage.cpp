#include "backend_stage.hpp"

#include <chrono>
#include <memory>
#include <optional>

#include "porter/backend/backend.hpp"
#include "porter/backend/robot_sdf.hpp"
#include "porter/baselines/safety_models.hpp"

namespace porter::app {

BackendRun run_backend(const PlanArgs& args, const RobotModel& model, const OccupancyGrid& grid_W,
                       const planner::WholeBodyPath& path, const Trajectory& warm_start,
                       const midend::MidendSettings& midend_settings, const planner::CollisionChecker& recheck) {
  using Clock = std::chrono::steady_clock;
  BackendRun run;
  run.budget_s = args.backend_budget_ms * 1e-3;
  baselines::SafetyModel model_kind = baselines::SafetyModel::kKcSvsdf;
  if (args.collision == CollisionArg::kSpheres) {
    model_kind = baselines::SafetyModel::kSpheres;
  } else if (args.safety == SafetyArg::kSvsdfPerLink) {
    model_kind = baselines::SafetyModel::kSvsdfPerLink;
  }
  run.safety_model = baselines::to_string(model_kind);

  const auto t0 = Clock::now();
  std::optional<backend::RobotSdf> sdf;
  if (model_kind != baselines::SafetyModel::kSpheres) sdf = backend::RobotSdf::build(model);
  run.setup_s = std::chrono::duration<double>(Clock::now() - t0).count();
  std::unique_ptr<backend::SafetyTerm> term = baselines::make_safety_term(model_kind, model, sdf ? &*sdf : nullptr);

  backend::BackendSettings settings;
  settings.problem = midend_settings;
  settings.max_iterations = args.backend_max_iterations;
  const backend::BackEnd solver(model, settings);
  run.result = solver.solve(path, warm_start, grid_W, *term, run.budget_s, &recheck);
  return run;
}

}  // namespace porter::app
